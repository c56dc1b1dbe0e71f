"""The ``[uncertainty]`` table of a vehicle file: validation, TOML round trips, provenance, sampling, vertices and
the fit's standard errors written by ``FlightFit.to_toml``."""

from __future__ import annotations

import math
import pickle
import tomllib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

import glidectl as gc
from glidectl.uncertainty import VERTEX_STDS

SLOCUM_TEXT = (Path(gc.__file__).parent / "vehicles" / "slocum_shallow.toml").read_text(encoding="utf-8")

#: Provenance of every preset recorded before the [uncertainty] table existed: a vehicle without the table keeps it.
PRESET_PROVENANCE = {
    "dc8_ctol": "96618725eb66ba17",
    "elevator_ch6": "ae2cae6aa587d57d",
    "rogue": "5a9203997c872a3e",
    "slocum_ch8": "1343c6ab0b42cfc2",
    "slocum_shallow": "04e92c2da1639da3",
    "sphere_ch5": "97cdd0f140b15e2f",
}

# slocum_shallow: K_M = -100, K_L = 132.5, K_D = 25, K_D0 = 2.15, J2 = 12, m_h = 43 (m_b = m0 + m - m_h - mbar = 0)
TABLE = """
[uncertainty]
K_M  = { min = -120.0, max = -70.0, source = "tow tank, +-25 %" }
K_D0 = { rel = 0.3, source = "engineering judgement" }
K_L  = { std = 10.0, source = "CFD spread" }
K_D  = { rel_std = 0.2, min = 0.0, source = "CFD spread" }
J2   = { std = 1.5, min = 9.0, max = 15.0, source = "CAD model" }

[uncertainty.correlation]
"K_L,K_D" = 0.6
"""


def _write(tmp_path: Path, text: str, name: str = "veh.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _slocum() -> gc.Vehicle:
    return gc.load_vehicle("slocum_shallow")


@pytest.fixture(scope="module")
def uncertain(tmp_path_factory: pytest.TempPathFactory) -> gc.Vehicle:
    return gc.load_vehicle(_write(tmp_path_factory.mktemp("unc"), SLOCUM_TEXT + TABLE))


# --------------------------------------------------------------------------------------------- 1. the table


def test_presets_keep_their_provenance():
    assert {n: gc.load_vehicle(n).provenance for n in gc.list_presets()} == PRESET_PROVENANCE
    for name in gc.list_presets():
        veh = gc.load_vehicle(name)
        assert dict(veh.uncertainty) == {} and veh.correlation == ()
        assert "[uncertainty]" not in veh.to_toml()
        assert veh.with_uncertainty({}).provenance == PRESET_PROVENANCE[name]
        assert not any(row[0].startswith("[uncertainty]") for row in veh.summary_rows())


def test_file_table_is_resolved_to_absolute_entries(uncertain):
    u = uncertain.uncertainty
    assert list(u) == ["J2", "K_L", "K_D0", "K_D", "K_M"]  # the order of the parameters
    assert u["K_M"] == gc.Uncertainty("interval", -120.0, -70.0, math.nan, "tow tank, +-25 %")
    assert (u["K_D0"].kind, u["K_D0"].low, u["K_D0"].high) == ("interval", 2.15 - 0.645, 2.15 + 0.645)
    assert math.isnan(u["K_D0"].std)
    assert (u["K_L"].kind, u["K_L"].low, u["K_L"].high, u["K_L"].std) == ("normal", -math.inf, math.inf, 10.0)
    assert (u["K_D"].kind, u["K_D"].low, u["K_D"].high) == ("normal", 0.0, math.inf)
    assert u["K_D"].std == pytest.approx(5.0, rel=1e-15)
    assert (u["J2"].low, u["J2"].high, u["J2"].std, u["J2"].truncated) == (9.0, 15.0, 1.5, True)
    assert uncertain.correlation == ((("K_D", "K_L"), 0.6),)
    assert uncertain.provenance != PRESET_PROVENANCE["slocum_shallow"]
    assert dict(uncertain.params) == dict(_slocum().params)
    rows = {r[0]: r for r in uncertain.summary_rows()}
    assert rows["[uncertainty] K_M"][1:] == ("uniform [-120, -70]", "kg/rad", "tow tank, +-25 %")
    assert rows["[uncertainty] correlation K_D,K_L"][1] == "0.6"


def test_to_toml_round_trip(uncertain, tmp_path):
    text = uncertain.to_toml()
    assert "[uncertainty]" in text and "[uncertainty.correlation]" in text
    assert "rel =" not in text and "rel_std" not in text  # written in absolute form
    back = gc.load_vehicle(_write(tmp_path, text, "back.toml"))
    assert dict(back.uncertainty) == dict(uncertain.uncertainty)
    assert list(back.uncertainty) == list(uncertain.uncertainty)
    assert back.correlation == uncertain.correlation
    assert back.provenance == uncertain.provenance
    assert dict(back.params) == dict(uncertain.params)
    again = gc.load_vehicle(_write(tmp_path, back.to_toml(), "again.toml"))
    assert again.to_toml() == back.to_toml()


def test_with_uncertainty_matches_the_file(uncertain):
    entries = {"K_M": {"min": -120.0, "max": -70.0, "source": "tow tank, +-25 %"},
               "K_D0": {"rel": 0.3, "source": "engineering judgement"},
               "K_L": {"std": 10.0, "source": "CFD spread"},
               "K_D": {"rel_std": 0.2, "min": 0.0, "source": "CFD spread"},
               "J2": {"std": 1.5, "min": 9.0, "max": 15.0, "source": "CAD model"}}
    veh = _slocum().with_uncertainty(entries, {("K_D", "K_L"): 0.6})
    assert dict(veh.uncertainty) == dict(uncertain.uncertainty)
    assert veh.correlation == uncertain.correlation and veh.provenance == uncertain.provenance
    same = _slocum().with_uncertainty({**entries, "correlation": {"K_L,K_D": 0.6}})
    assert same.correlation == uncertain.correlation
    # Uncertainty objects are accepted as entries; a missing source is recorded as given here
    bare = _slocum().with_uncertainty({"K_M": uncertain.uncertainty["K_M"], "K_L": {"std": 3.0}})
    assert bare.uncertainty["K_M"] == uncertain.uncertainty["K_M"]
    assert bare.uncertainty["K_L"].source == "Vehicle.with_uncertainty"
    assert dict(uncertain.with_uncertainty({}).uncertainty) == {}


def test_the_table_survives_overrides_pickling_and_actuators(uncertain):
    moved = uncertain.with_overrides(K_M=-80.0, J1=5.0)
    assert dict(moved.uncertainty) == dict(uncertain.uncertainty)
    assert moved.correlation == uncertain.correlation
    beyond = uncertain.with_overrides(K_M=-150.0, K_D=0.001, J2=20.0)  # outside the K_M and J2 bounds
    assert set(beyond.uncertainty) == {"K_L", "K_D", "K_D0"}
    assert beyond.correlation == uncertain.correlation
    pair = _slocum().with_uncertainty({"K_L": {"std": 20.0, "min": 120.0, "max": 150.0}, "K_D": {"std": 5.0}},
                                      {"K_L,K_D": 0.5})
    alone = pair.with_overrides(K_L=160.0)  # K_L leaves its truncation: its entry and correlation go
    assert set(alone.uncertainty) == {"K_D"} and alone.correlation == () and pair.correlation != ()
    no_kd = uncertain.with_overrides(K_D=-0.0)  # inside K_D's truncation [0, inf): kept
    assert "K_D" in no_kd.uncertainty
    loaded = gc.load_vehicle(_write(Path(uncertain.path).parent, SLOCUM_TEXT + TABLE, "over.toml"), K_M=-150.0)
    assert dict(loaded.uncertainty) == dict(uncertain.with_overrides(K_M=-150.0).uncertainty)
    assert "K_M" not in loaded.uncertainty and len(loaded.uncertainty) == 4
    copy = pickle.loads(pickle.dumps(uncertain))
    assert dict(copy.uncertainty) == dict(uncertain.uncertainty) and copy.correlation == uncertain.correlation
    assert copy.provenance == uncertain.provenance
    acts = uncertain.with_actuators(elevator={"min": -0.3, "max": 0.3})
    assert dict(acts.uncertainty) == dict(uncertain.uncertainty) and acts.correlation == uncertain.correlation
    free = _slocum().with_actuators(r_P1=None).with_uncertainty({"r_P1": {"min": -0.01, "max": 0.01}})
    assert free.uncertainty["r_P1"].kind == "interval"
    with pytest.raises(gc.VehicleFileError, match=r"'r_P1' is set by \[actuators\] r_P1"):
        free.with_actuators(r_P1={"min": -0.025, "max": 0.025, "rate": 0.005})


def test_law_switch_drops_entries_of_the_old_law(uncertain):
    sg = uncertain.with_hydrodynamics("seaglider", hd_a=0.003, hd_b=0.01, hd_c=1e-5, length=1.8)
    assert set(sg.uncertainty) == {"J2", "K_M"} and sg.correlation == ()
    gf = _slocum().with_hydrodynamics("gliderflight", Cd0=0.15).with_uncertainty(
        {"AR": {"rel": 0.1}, "Cd0": {"rel_std": 0.2}})
    assert gf.uncertainty["AR"].low == pytest.approx(6.3)
    fitted = gf.with_hydrodynamics(Cd0=0.16, AR=9.0)  # AR leaves its interval: its entry goes
    assert set(fitted.uncertainty) == {"Cd0"}


# --------------------------------------------------------------------------------------------- 2. bad tables


BAD_ENTRIES = [
    ('K_MM = { min = -120.0, max = -80.0, source = "x" }', ("'K_MM'", "did you mean 'K_M'")),
    ('K_M = { min = -60.0, max = -40.0, source = "x" }', ("'K_M'", "excludes the nominal value -100")),
    ('K_L = { std = 0.0, source = "x" }', ("'K_L'", "'std' must be > 0")),
    ('K_L = { std = -2.0, source = "x" }', ("'K_L'", "'std' must be > 0")),
    ('K_L = { rel_std = 0.0, source = "x" }', ("'K_L'", "'rel_std' must be > 0")),
    ('K_L = { rel = -0.1, source = "x" }', ("'K_L'", "'rel' must be > 0")),
    ('K_M = { min = -80.0, max = -120.0, source = "x" }', ("'K_M'", "must be < max")),
    ('K_M = { min = -100.0, max = -100.0, source = "x" }', ("'K_M'", "must be < max")),
    ('K_L = { std = 2.0, min = 140.0, max = 130.0, source = "x" }', ("'K_L'", "must be < max")),
    ('K_L = { std = inf, source = "x" }', ("'K_L'", "'std' must be finite")),
    ('K_M = { min = nan, max = -80.0, source = "x" }', ("'K_M'", "'min' must be finite")),
    ('K_L = { std = true, source = "x" }', ("'K_L'", "must be a real number")),
    ('K_M = { min = -120.0, max = -80.0, sorce = "x" }', ("'K_M'", "unknown field", "did you mean 'source'")),
    ('K_L = { std = 2.0, rel_std = 0.1, source = "x" }', ("'K_L'", "not both")),
    ('K_L = { rel = 0.1, min = 100.0, source = "x" }', ("'K_L'", "give one of them")),
    ('K_L = { rel = 0.1, std = 2.0, source = "x" }', ("'K_L'", "'rel' makes an interval")),
    ('K_L = { min = 100.0, source = "x" }', ("'K_L'", "give an interval")),
    ('K_L0 = { rel = 0.3, source = "x" }', ("'K_L0'", "nominal value 0")),
    ('K_L0 = { rel_std = 0.3, source = "x" }', ("'K_L0'", "nominal value 0")),
    ('J2 = { min = -1.0, max = 20.0, source = "x" }', ("'J2'", "> 0")),
    ('K_D = { std = 5.0, min = -1.0, source = "x" }', ("'K_D'", ">= 0")),
    ('K_M = 3.0', ("'K_M'", "inline table")),
    ('K_M = { min = -1e300, max = 1e300, source = "x" }', ("'K_M'", "plausibility limit")),
    ('K_M = { rel = 1e20, source = "x" }', ("'K_M'", "plausibility limit")),
    ('K_L = { std = 1e13, source = "x" }', ("'K_L'", "plausibility limit")),
    ('K_M = { min = -120.0, max = -80.0 }', ("'K_M'", "non-empty 'source'")),
    ('K_M = { min = -120.0, max = -80.0, source = " " }', ("'K_M'", "non-empty 'source'")),
    ('m0 = { min = -0.1, max = 0.1, source = "x" }', ("'m0'", "set by [actuators] m0")),
    ('r_P3 = { rel = 0.1, source = "x" }', ("'r_P3'", "fixed setting of [actuators] r_P3")),
    ('rudder = { rel = 0.1, source = "x" }', ("'rudder'", "set by [actuators] rudder")),
    ('elevator = { rel = 0.1, source = "x" }', ("'elevator'", "is an actuator")),
    ('m1 = { rel = 0.1, source = "x" }', ("'m1'", "has no value in this vehicle")),
    ('hd_a = { rel = 0.1, source = "x" }', ("'hd_a'", "seaglider")),
]

BAD_CORRELATIONS = [
    ('"K_L,K_M" = 0.5', ("'K_M'", "is an interval")),
    ('"K_L,K_DD" = 0.5', ("'K_DD'", "did you mean 'K_D'")),
    ('"K_L,K_D" = 1.5', ("K_L,K_D", "[-1, 1]")),
    ('"K_L,K_D" = nan', ("K_L,K_D", "finite")),
    ('"K_L,K_L" = 0.5', ("'K_L'", "twice")),
    ('"K_L" = 0.5', ("'K_L'", "two coefficients")),
    ('"K_L,K_D" = 0.5\n"K_D,K_L" = 0.5', ("'K_L'", "'K_D'", "given twice")),
    ('"K_L,K_D" = 0.9\n"K_L,J2" = 0.9\n"K_D,J2" = -0.9', ("K_D,K_L = 0.9", "positive semidefinite")),
]

_NORMALS = ('[uncertainty]\nK_M = { min = -120.0, max = -80.0, source = "x" }\nK_L = { std = 10.0, source = "x" }\n'
            'K_D = { std = 5.0, source = "x" }\nJ2 = { std = 1.0, source = "x" }\n')


@pytest.mark.parametrize(("entry", "words"), BAD_ENTRIES, ids=[e[0][:40] for e in BAD_ENTRIES])
def test_bad_entry_in_a_file(tmp_path, entry, words):
    path = _write(tmp_path, SLOCUM_TEXT + "\n[uncertainty]\n" + entry + "\n")
    with pytest.raises(gc.VehicleFileError) as info:
        gc.load_vehicle(path)
    msg = str(info.value)
    assert str(path) in msg and "[uncertainty]" in msg
    for w in words:
        assert w in msg, (w, msg)


@pytest.mark.parametrize(("entry", "words"), BAD_CORRELATIONS, ids=[e[0][:40] for e in BAD_CORRELATIONS])
def test_bad_correlation_in_a_file(tmp_path, entry, words):
    path = _write(tmp_path, SLOCUM_TEXT + _NORMALS + "\n[uncertainty.correlation]\n" + entry + "\n")
    with pytest.raises(gc.VehicleFileError) as info:
        gc.load_vehicle(path)
    msg = str(info.value)
    assert str(path) in msg and "[uncertainty.correlation]" in msg
    for w in words:
        assert w in msg, (w, msg)


@pytest.mark.parametrize(("entry", "words"), [e for e in BAD_ENTRIES if "non-empty 'source'" not in e[1]],
                         ids=[e[0][:40] for e in BAD_ENTRIES if "non-empty 'source'" not in e[1]])
def test_bad_entry_through_with_uncertainty(entry, words):
    key, value = next(iter(tomllib.loads(entry).items()))
    with pytest.raises(gc.VehicleFileError) as info:
        _slocum().with_uncertainty({key: value})
    msg = str(info.value)
    assert "vehicle 'slocum_shallow'" in msg
    for w in words:
        assert w in msg, (w, msg)


def test_type_errors_and_both_correlations():
    veh = _slocum()
    with pytest.raises(gc.ArgumentTypeError, match="mapping"):
        veh.with_uncertainty([("K_M", {"rel": 0.1})])
    with pytest.raises(gc.VehicleFileError, match="given twice"):
        veh.with_uncertainty({"K_L": {"std": 1.0}, "K_D": {"std": 1.0}, "correlation": {"K_L,K_D": 0.1}},
                             {"K_L,K_D": 0.1})


@pytest.mark.parametrize(("text", "match"), [
    ("uncertainty = 3\n" + SLOCUM_TEXT, r"\[uncertainty\] must be a table"),
    (SLOCUM_TEXT + "\n[uncertainty]\ncorrelation = 3\n", r"\[uncertainty.correlation\] must be a table"),
    (SLOCUM_TEXT + "\n[uncertanity]\n", r"did you mean \[uncertainty\]"),
])
def test_bad_tables(tmp_path, text, match):
    with pytest.raises(gc.VehicleFileError, match=match):
        gc.load_vehicle(_write(tmp_path, text))


def test_uncertainty_objects_check_themselves():
    assert gc.Uncertainty("interval", 1.0, 2.0) == gc.Uncertainty("interval", 1.0, 2.0)  # nan std compare equal
    assert gc.Uncertainty("normal", -math.inf, math.inf, 1.0) != gc.Uncertainty("normal", -math.inf, math.inf, 2.0)
    for args, match in [(("box", 1.0, 2.0), "kind"), (("interval", 2.0, 1.0), "min < max"),
                        (("interval", 1.0, math.inf), "finite bounds"), (("interval", 1.0, 2.0, 0.5), "no std"),
                        (("normal", 1.0, 2.0), "std > 0"), (("normal", 1.0, 2.0, -1.0), "std > 0"),
                        (("interval", "1", 2.0), "real number")]:
        with pytest.raises(gc.VehicleFileError, match=match):
            gc.Uncertainty(*args)


# --------------------------------------------------------------------------------------------- 3. sampling


def test_sample_statistics(uncertain):
    values, keys = uncertain.sample_overrides(4000, seed=3)
    assert values.shape == (4000, 5) and keys == tuple(uncertain.uncertainty)
    col = {k: values[:, i] for i, k in enumerate(keys)}
    # interval: uniform, inside, reaching both ends
    km = col["K_M"]
    assert km.min() >= -120.0 and km.max() <= -70.0
    assert km.min() < -119.9 and km.max() > -70.1
    assert km.mean() == pytest.approx(-95.0, abs=0.8)
    assert km.std() == pytest.approx(50.0 / math.sqrt(12.0), rel=0.04)
    kd0 = col["K_D0"]
    assert kd0.min() >= 2.15 - 0.645 and kd0.max() <= 2.15 + 0.645
    # untruncated normal
    assert col["K_L"].mean() == pytest.approx(132.5, abs=0.5)
    assert col["K_L"].std() == pytest.approx(10.0, rel=0.04)
    # truncated normals: inside their bounds, mean and std of the truncated law
    j2 = col["J2"]
    assert j2.min() >= 9.0 and j2.max() <= 15.0
    law = stats.truncnorm((9.0 - 12.0) / 1.5, (15.0 - 12.0) / 1.5, loc=12.0, scale=1.5)
    assert j2.mean() == pytest.approx(law.mean(), abs=0.06)
    assert j2.std() == pytest.approx(law.std(), rel=0.04)
    assert col["K_D"].min() >= 0.0
    # correlation of the two correlated normals
    assert np.corrcoef(col["K_L"], col["K_D"])[0, 1] == pytest.approx(0.6, abs=0.04)
    assert abs(np.corrcoef(col["K_L"], col["K_M"])[0, 1]) < 0.05


def test_correlated_truncated_normals_stay_inside():
    veh = _slocum().with_uncertainty({"K_L": {"std": 20.0, "min": 120.0, "max": 150.0},
                                      "K_D": {"std": 5.0, "min": 20.0}}, {"K_L,K_D": -0.8})
    values, keys = veh.sample_overrides(2000, seed=1)
    kl, kd = values[:, keys.index("K_L")], values[:, keys.index("K_D")]
    assert kl.min() >= 120.0 and kl.max() <= 150.0 and kd.min() >= 20.0
    assert np.corrcoef(kl, kd)[0, 1] < -0.3


def test_seeded_reproducibility(uncertain):
    a, _ = uncertain.sample_overrides(10, seed=7)
    b, _ = uncertain.sample_overrides(10, seed=7)
    c, _ = uncertain.sample_overrides(5, seed=7)
    d, _ = uncertain.sample_overrides(10, seed=8)
    assert np.array_equal(a, b)
    assert np.array_equal(a[:5], c)
    assert not np.any(a == d)
    sample = uncertain.sample(5, seed=7)
    assert np.array_equal(sample.values, c) and sample.seed == 7 and sample.method == "random"
    assert not sample.values.flags.writeable


def test_sampled_vehicles_record_their_overrides(uncertain):
    sample = uncertain.sample(6, seed=2)
    assert sample.valid.all() and len(sample) == 6 and sample.errors == (None,) * 6
    assert sample.vehicle is uncertain and sample.provenance == uncertain.provenance
    for row, veh in zip(sample.values, sample, strict=True):
        for key, value in zip(sample.keys, row, strict=True):
            assert veh.params[key] == value and veh.overrides[key] == value and veh.sources[key] == "override"
        assert dict(veh.uncertainty) == dict(uncertain.uncertainty)
    assert sample[0] is sample.vehicles[0] and sample[-1] is sample.vehicles[-1]
    assert len({v.provenance for v in sample}) == 6
    assert "6 random samples" in sample.summary() and "6 valid" in sample.summary()


def test_invalid_samples_are_recorded_not_raised():
    # m_b = m0 + m - m_h - mbar = 0 at the nominal m_h = 43 kg: every m_h above it makes the buoyancy mass negative
    veh = _slocum().with_uncertainty({"m_h": {"min": 40.0, "max": 46.0, "source": "ballast not weighed"}})
    sample = veh.sample(200, seed=0)
    heavy = sample.values[:, 0] > 43.0
    assert 60 < heavy.sum() < 140
    assert np.array_equal(sample.valid, ~heavy)
    assert len(sample) == int((~heavy).sum()) == len(list(sample))
    for ok, veh_i, err in zip(sample.valid, sample.vehicles, sample.errors, strict=True):
        assert (veh_i is not None) == ok and (err is None) == ok
        if not ok:
            assert "m_b" in err and "negative" in err
    first = int(np.flatnonzero(heavy)[0])
    assert f"sample {first}" in sample.summary()
    with pytest.raises(gc.VehicleFileError, match=rf"sample {first} of vehicle 'slocum_shallow' is invalid.*m_b"):
        veh.sample(200, seed=0, on_invalid="raise")
    # the tail of a normal entry reaching below a positive parameter's bound
    wide = _slocum().with_uncertainty({"J2": {"std": 12.0}})
    s = wide.sample(100, seed=4)
    negative = s.values[:, 0] <= 0
    assert negative.any() and np.array_equal(s.valid, ~negative)
    assert all("'J2'" in e and "> 0" in e for e in s.errors if e is not None)


def test_sampling_needs_a_table_and_good_arguments(uncertain):
    veh = _slocum()
    for call in (lambda: veh.sample(3), lambda: veh.sample_overrides(3), lambda: veh.vertices()):
        with pytest.raises(gc.ArgumentError, match=r"no \[uncertainty\] entries.*with_uncertainty"):
            call()
    with pytest.raises(gc.ArgumentError, match="n must be"):
        uncertain.sample(0)
    with pytest.raises(gc.ArgumentTypeError, match="n must be an integer"):
        uncertain.sample(2.0)
    with pytest.raises(gc.ArgumentError, match="seed"):
        uncertain.sample_overrides(2, seed=-1)
    with pytest.raises(gc.ArgumentError, match="on_invalid"):
        uncertain.sample(2, on_invalid="skip")
    with pytest.raises(gc.ArgumentTypeError, match="max_vertices"):
        uncertain.vertices(max_vertices=None)


@settings(max_examples=40, deadline=None)
@given(nominal=st.floats(-1e3, 1e3), below=st.floats(0.0, 1e3), above=st.floats(1e-3, 1e3),
       seed=st.integers(0, 2**32))
def test_interval_samples_stay_within_bounds(nominal, below, above, seed):
    veh = _slocum().with_overrides(K_M=nominal)
    low, high = nominal - below, nominal + above
    if not low < high:
        return
    veh = veh.with_uncertainty({"K_M": {"min": low, "max": high}})
    unc = veh.uncertainty["K_M"]
    assert unc.low <= veh.K_M <= unc.high
    values, _ = veh.sample_overrides(50, seed=seed)
    assert np.all((values >= low) & (values <= high))
    corners = veh.vertices().values
    assert sorted(corners[:, 0].tolist()) == [low, high]


@settings(max_examples=30, deadline=None)
@given(nominal=st.floats(-1e3, 1e3).filter(lambda x: abs(x) > 1e-6), rel=st.floats(1e-3, 0.9))
def test_relative_interval_is_symmetric_about_the_nominal(nominal, rel):
    veh = _slocum().with_overrides(K_M=nominal).with_uncertainty({"K_M": {"rel": rel}})
    unc = veh.uncertainty["K_M"]
    assert unc.low == nominal - abs(nominal) * rel and unc.high == nominal + abs(nominal) * rel
    assert unc.low < nominal < unc.high


# --------------------------------------------------------------------------------------------- 4. vertices


def test_vertices_are_all_the_corners(uncertain):
    three = _slocum().with_uncertainty({"K_M": {"min": -120.0, "max": -80.0}, "K_L": {"std": 10.0},
                                        "K_D": {"std": 5.0, "min": 20.0}})
    v = three.vertices()
    assert v.values.shape == (8, 3) and v.method == "vertices" and len(v) == 8
    boxes = {k: three.uncertainty[k].box(three.params[k]) for k in v.keys}
    assert boxes["K_L"] == (132.5 - VERTEX_STDS * 10.0, 132.5 + VERTEX_STDS * 10.0)
    assert boxes["K_D"] == (20.0, 25.0 + VERTEX_STDS * 5.0)
    for i, key in enumerate(v.keys):
        assert set(v.values[:, i]) == set(boxes[key])
    assert len({tuple(r) for r in v.values}) == 8
    # binary order: the first key varies slowest
    assert v.values[0].tolist() == [boxes[k][0] for k in v.keys]
    assert v.values[-1].tolist() == [boxes[k][1] for k in v.keys]
    assert v.values[1, -1] == boxes[v.keys[-1]][1] and v.values[4, 0] == boxes[v.keys[0]][1]
    assert uncertain.vertices().values.shape == (32, 5)
    assert uncertain.vertices(max_vertices=32).values.shape == (32, 5)


def test_vertices_subset_when_corners_do_not_fit(uncertain):
    v = uncertain.vertices(max_vertices=20, seed=5)
    k = 5
    nominal = np.array([uncertain.params[key] for key in v.keys])
    lo, hi = (np.array(c) for c in zip(*(uncertain.uncertainty[key].box(uncertain.params[key]) for key in v.keys),
                                         strict=True))
    assert v.values.shape == (20, k)
    assert np.array_equal(v.values[0], nominal)
    for i in range(k):
        for j, bound in enumerate((lo, hi)):
            row = v.values[1 + 2 * i + j]
            expect = nominal.copy()
            expect[i] = bound[i]
            assert np.array_equal(row, expect)
    corners = v.values[2 * k + 1:]
    assert np.all((corners == lo) | (corners == hi))
    assert len({tuple(r) for r in corners}) == 20 - 2 * k - 1
    assert np.array_equal(uncertain.vertices(max_vertices=20, seed=5).values, v.values)
    assert not np.array_equal(uncertain.vertices(max_vertices=20, seed=6).values, v.values)
    with pytest.raises(gc.ArgumentError, match="at least 11"):
        uncertain.vertices(max_vertices=10)


def test_vertices_of_many_coefficients():
    keys = ["J1", "J2", "J3", "K_L", "K_D", "K_D0", "K_M", "K_beta", "K_MY", "K_MR", "m_f1", "m_f2", "m_f3"]
    veh = _slocum().with_uncertainty({k: {"rel": 0.1} for k in keys})
    v = veh.vertices(max_vertices=1024, seed=0)
    assert v.values.shape == (1024, 13) and len(set(map(tuple, v.values))) == 1024


# --------------------------------------------------------------------------------------------- 5. fitted files


def _synthetic_record(veh: gc.Vehicle) -> gc.DiveRecord:
    """A dive and a climb whose depth follows the vehicle's own steady glide, with noise."""
    n, dt = 200, 10.0
    i = np.arange(n)
    pitch = np.where(i < n // 2, -0.45, 0.45) * (1 + 0.2 * np.sin(i / 7.0))
    vol = np.where(i < n // 2, -2.5e-4, 2.5e-4) * (1 + 0.3 * np.cos(i / 5.0))
    time = i * dt
    first = gc.DiveRecord.from_arrays(time=time, depth=np.linspace(0.0, 100.0, n), pitch=pitch,
                                      buoyancy_volume=vol)
    w = gc.predict_flight(veh, first).vertical_speed + 0.002 * np.random.default_rng(1).standard_normal(n)
    depth = 5.0 + np.concatenate(([0.0], np.cumsum(-0.5 * (w[1:] + w[:-1]) * dt)))
    return gc.DiveRecord.from_arrays(time=time, depth=depth, pitch=pitch, buoyancy_volume=vol,
                                     source="synthetic dive")


def test_fit_writes_its_standard_errors(tmp_path):
    veh = _slocum().with_hydrodynamics(mass=70.0, volume=70.0 / 1025.0).with_uncertainty(
        {"K_M": {"rel": 0.2, "source": "guess"}, "K_D": {"std": 1.0, "source": "old"}})
    fit = gc.fit_flight_model(veh, _synthetic_record(veh), fit=("volume", "K_D0", "K_D"),
                              mask=np.ones(200, dtype=bool))
    back = gc.load_vehicle(fit.to_toml(tmp_path / "fitted.toml"))
    src = "standard error of the fit to synthetic dive"
    for key in fit.params:
        u = back.uncertainty[key]
        assert (u.kind, u.std, u.low, u.high, u.source) == ("normal", fit.stderr[key], -math.inf, math.inf, src)
    assert back.uncertainty["K_M"].source == "guess"  # the vehicle's other entries are kept
    names = list(fit.params)
    expect = {tuple(sorted((names[i], names[j]))): fit.correlation[i, j] for i in range(3) for j in range(i + 1, 3)
              if abs(fit.correlation[i, j]) > 0.05}
    assert ("K_D", "K_D0") in expect and dict(back.correlation) == pytest.approx(expect, rel=1e-15)
    assert dict(back.params) == dict(fit.vehicle.params)
    assert back.provenance != fit.provenance
    assert back.with_uncertainty({}).provenance == fit.vehicle.with_uncertainty({}).provenance
