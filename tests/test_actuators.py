"""The ``[actuators]`` table of vehicle files: parsing, validation, limits used by the models (issue 16 part 1)."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import glidectl as gc
from glidectl.models.buoyancy_glider import actuator_limits
from glidectl.params import ACTUATOR_SPECS, Actuator

HEAD = '''[vehicle]
name = "t"
kind = "underwater_glider"

[parameters]
g    = { value = 9.8,   unit = "m/s^2",      source = "s" }
m1   = { value = 28.0,  unit = "kg",         source = "s" }
m3   = { value = 28.0,  unit = "kg",         source = "s" }
mbar = { value = 0.0,   unit = "kg",         source = "s" }
J2   = { value = 0.02,  unit = "kg*m^2",     source = "s" }
K_D0 = { value = 2.0,   unit = "kg/m",       source = "s" }
K_D  = { value = 80.0,  unit = "kg/m/rad^2", source = "s" }
K_L0 = { value = 0.0,   unit = "kg/m",       source = "s" }
K_L  = { value = 75.0,  unit = "kg/m/rad",   source = "s" }
K_M0 = { value = 1.0,   unit = "kg",         source = "s" }
K_M  = { value = -50.0, unit = "kg/rad",     source = "s" }
K_q  = { value = -2.0,  unit = "kg*s/rad",   source = "s" }
'''


def _load(tmp_path, actuators: str, extra: str = ""):
    p = tmp_path / "v.toml"
    p.write_text(HEAD + extra + "\n[actuators]\n" + actuators, encoding="utf-8")
    return gc.load_vehicle(p)


def test_table_parsed_with_units_rates_and_fixed(tmp_path):
    veh = _load(tmp_path, 'm0 = { min = -0.25, max = 0.25, rate = 0.01, unit = "kg", source = "pump" }\n'
                          'r_P1 = { min = -0.025, max = 0.025, rate = 0.005, unit = "m", source = "battery" }\n'
                          'r_P3 = { fixed = 0.035, unit = "m", source = "ballast" }\n')
    m0, rp1, rp3 = veh.actuators["m0"], veh.actuators["r_P1"], veh.actuators["r_P3"]
    assert (m0.min, m0.max, m0.rate, m0.unit, m0.source) == (-0.25, 0.25, 0.01, "kg", "pump")
    assert rp1.actuated and not rp3.actuated and rp3.bounds == (0.035, 0.035) and rp3.rate == 0.0
    assert veh.r_P3 == 0.035 and "ballast" in veh.sources["r_P3"]        # a fixed part is the nominal setting
    assert veh.actuator_bounds("r_P2", default=(-1.0, 1.0)) == (-1.0, 1.0)
    assert rp1.contains(0.025) and not rp1.contains(0.0251)
    np.testing.assert_array_equal(rp1.clip([-1.0, 0.01, 1.0]), [-0.025, 0.01, 0.025])
    rows = {r[0]: r for r in veh.summary_rows()}                     # the report parameter table lists them
    assert rows["[actuator] m0"][1] == "[-0.25, 0.25] kg, 0.01 kg/s" and rows["[actuator] m0"][3] == "pump"
    assert rows["[actuator] r_P3"][1] == "fixed 0.035 m"


def test_pickle_and_provenance(tmp_path):
    veh = _load(tmp_path, 'm0 = { min = -0.25, max = 0.25, rate = 0.01, unit = "kg", source = "pump" }\n')
    back = pickle.loads(pickle.dumps(veh))
    assert back.actuators == veh.actuators and back.provenance == veh.provenance
    wider = veh.with_actuators(m0={"min": -0.5, "max": 0.5, "rate": 0.01})
    assert wider.provenance != veh.provenance                      # limits change results, so provenance
    assert "m0" not in veh.with_actuators(m0=None).actuators
    assert veh.with_actuators(m0=None).provenance != veh.provenance


@pytest.mark.parametrize(("table", "match"), [
    ('pump = { min = 0, max = 1, unit = "kg", source = "s" }\n', "unknown actuator 'pump'"),
    ('K_M = { min = 0, max = 1, unit = "kg", source = "s" }\n', "is a parameter, not an actuator"),
    ('m0 = { min = 0.3, max = 0.2, unit = "kg", source = "s" }\n', "min = 0.3 must be < max = 0.2"),
    ('m0 = { min = -0.2, max = 0.2, rate = -0.01, unit = "kg", source = "s" }\n', "rate must be > 0"),
    ('m0 = { min = -0.2, max = 0.2, rate = 0.0, unit = "kg", source = "s" }\n', "rate must be > 0"),
    ('r_P3 = { fixed = 0.05, min = -0.03, max = 0.03, unit = "m", source = "s" }\n', "outside its range"),
    ('r_P3 = { fixed = 0.05, rate = 0.01, unit = "m", source = "s" }\n', "cannot have a 'rate'"),
    ('m0 = { min = -0.2, max = 0.2, unit = "l", source = "s" }\n', "unit 'l'"),
    ('m0 = { min = -0.2, max = 0.2, unit = "kg" }\n', "needs a non-empty 'source'"),
    ('m0 = { min = -0.2, max = 0.2, source = "s" }\n', "needs a 'unit'"),
    ('m0 = { min = -0.2, unit = "kg", source = "s" }\n', "needs both 'min' and 'max'"),
    ('m0 = { rate = 0.1, unit = "kg", source = "s" }\n', "needs a range"),
    ('m0 = { min = -0.2, max = 0.2, speed = 1, unit = "kg", source = "s" }\n', "unknown field"),
    ('m0 = { min = "a", max = 0.2, unit = "kg", source = "s" }\n', "must be a real number"),
    ('m0 = { min = nan, max = 0.2, unit = "kg", source = "s" }\n', "finite"),
    ('m0 = 0.2\n', "inline table"),
])
def test_bad_actuator_tables_refused(tmp_path, table, match):
    with pytest.raises(gc.VehicleFileError, match=match):
        _load(tmp_path, table)


def test_nominal_settings_must_agree_with_the_table(tmp_path):
    with pytest.raises(gc.VehicleFileError, match="outside the actuator range"):
        _load(tmp_path, 'm0 = { min = -0.2, max = 0.2, unit = "kg", source = "s" }\n',
              'm0 = { value = 0.7, unit = "kg", source = "s" }\n')
    with pytest.raises(gc.VehicleFileError, match="disagree"):
        _load(tmp_path, 'r_P3 = { fixed = 0.03, unit = "m", source = "s" }\n',
              'r_P3 = { value = 0.04, unit = "m", source = "s" }\n')


@pytest.mark.parametrize("key", ["u2_max", "u4_max", "m0_max"])
def test_old_limit_keys_point_to_the_table(tmp_path, key):
    p = tmp_path / "old.toml"
    p.write_text(HEAD + f'{key} = {{ value = 0.1, unit = "kg", source = "s" }}\n', encoding="utf-8")
    with pytest.raises(gc.VehicleFileError, match=r"moved to the \[actuators\] table"):
        gc.load_vehicle(p)
    with pytest.raises(gc.VehicleFileError, match="with_actuators"):
        gc.load_vehicle("sphere_ch5", **{key: 0.1})


def test_ctol_has_no_actuator_table():
    veh = gc.load_vehicle("dc8_ctol")
    with pytest.raises(gc.VehicleFileError, match="underwater gliders only"):
        veh.with_actuators(m0={"min": -1.0, "max": 1.0})


def test_presets_moved_their_limits():
    sph, elev = gc.load_vehicle("sphere_ch5"), gc.load_vehicle("elevator_ch6")
    assert sph.actuators["m0"].bounds == (-1.0, 1.0) and sph.actuators["m0"].rate == 0.02
    lim = actuator_limits(elev)
    assert (lim.u2_min, lim.u2_max, lim.m0_min, lim.m0_max, lim.u4_max) == (-0.2, 0.2, -4.0, 4.0, 0.05)
    assert actuator_limits(gc.load_vehicle("rogue")).m0_max == math.inf


def test_asymmetric_pump_range_is_enforced():
    veh = gc.load_vehicle("sphere_ch5").with_actuators(m0={"min": -0.3, "max": 0.8, "rate": 0.02})
    lim = actuator_limits(veh)
    rate = lim.pump(np.array([0.8, 0.8, -0.3, -0.3, 0.0]), np.array([1.0, -1.0, -1.0, 1.0, -1.0]))
    np.testing.assert_array_equal(rate, [0.0, -0.02, 0.0, 0.02, -0.02])
    with pytest.raises(gc.ModelError, match="must contain 0"):
        actuator_limits(veh.with_actuators(m0={"min": 0.1, "max": 0.8}))


@settings(max_examples=60, deadline=None)
@given(lo=st.floats(-10, 10), width=st.floats(1e-6, 10), rate=st.floats(1e-6, 1e3),
       v=st.floats(-30, 30))
def test_actuator_contains_and_clip_agree(lo, width, rate, v):
    a = Actuator("r_P1", min=lo, max=lo + width, rate=rate, unit="m")
    c = float(a.clip(v))
    assert a.min <= c <= a.max and a.contains(c)
    assert (c == v) == (a.min <= v <= a.max)


def test_every_spec_key_is_documented():
    assert set(ACTUATOR_SPECS) == {"m0", "r_P1", "r_P2", "r_P3", "roll", "elevator", "rudder"}
    assert all(s.unit in ("kg", "m", "rad") for s in ACTUATOR_SPECS.values())
