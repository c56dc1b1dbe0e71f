"""Lift and drag laws of ``[hydrodynamics]``: thesis, Seaglider and gliderflight; steady flight against closed forms
and against gliderflight itself; vehicle-file validation of the new tables; ``to_toml`` round trips; ``law_start``."""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import warnings
from pathlib import Path

import dbdreader
import gliderflight.gliderflight as gfm
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq, fsolve

import glidectl as gc
from glidectl.params import THESIS_LIFT_DRAG_KEYS

FAST = settings(max_examples=40, deadline=None)

SLOCUM_TEXT = (Path(gc.__file__).parent / "vehicles" / "slocum_shallow.toml").read_text(encoding="utf-8")
AMMONITE = os.path.join(os.path.dirname(dbdreader.__file__), "data", "ammonite-2008-028-01-000.mbd")

SEAGLIDER_TABLE = """
[hydrodynamics]
law = "seaglider"
hd_a = { value = 0.003836, unit = "1/deg", source = "Seaglider basestation default" }
hd_b = { value = 0.010078, unit = "Pa^(1/4)", source = "Seaglider basestation default" }
hd_c = { value = 9.8e-6, unit = "1/deg^2", source = "Seaglider basestation default" }
length = { value = 1.8, unit = "m", source = "Seaglider hull length (Eriksen et al. 2001)" }
density = { value = 1027, unit = "kg/m^3", source = "test water" }
"""
SG = {"hd_a": 0.003836, "hd_b": 0.010078, "hd_c": 9.8e-6, "length": 1.8, "density": 1027.0}


def _without_thesis_lift_drag(text: str) -> str:
    """slocum_shallow's text with K_L0, K_L, K_D0, K_D removed from [parameters]."""
    out = re.sub(r"(?m)^(K_L0|K_L|K_D0|K_D)\s*=.*\n", "", text)
    assert out.count("\n") == text.count("\n") - 4
    return out


def _insert_before_actuators(text: str, table: str) -> str:
    assert text.count("[actuators]") == 1
    return text.replace("[actuators]", table.strip() + "\n\n[actuators]")


def _write(tmp_path: Path, text: str, name: str = "veh.toml") -> Path:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def _seaglider_text() -> str:
    return _insert_before_actuators(_without_thesis_lift_drag(SLOCUM_TEXT), SEAGLIDER_TABLE)


@pytest.fixture(scope="module")
def seaglider(tmp_path_factory: pytest.TempPathFactory) -> gc.Vehicle:
    return gc.load_vehicle(_write(tmp_path_factory.mktemp("sg"), _seaglider_text(), "seaglider.toml"))


def _gliderflight_model() -> gfm.SteadyStateGliderModel:
    gm = gfm.SteadyStateGliderModel(rho0=1025)
    gm.define(mg=70, Vg=0.0684, Cd0=0.0939, ah=3.8, epsilon=5e-10, Cd1=10.5, S=0.1)
    return gm


def _gliderflight_vehicle(gm: gfm.SteadyStateGliderModel) -> gc.Vehicle:
    return gc.load_vehicle("slocum_shallow").with_hydrodynamics(
        "gliderflight", Cd0=gm.Cd0, Cd1=gm.Cd1, ah=gm.ah, S=gm.S, aw=float(gm.aw), mass=float(gm.mg),
        volume=gm.Vg, compressibility=gm.epsilon, density=1025.0)


THESIS = gc.load_vehicle("slocum_shallow")
THESIS_ASYM = gc.load_vehicle("slocum_shallow", K_L0=3.0)  # zero-lift angle -K_L0/K_L != 0
GLIDERFLIGHT = _gliderflight_vehicle(_gliderflight_model())


# --------------------------------------------------------------------------------------------- 1. thesis default


@pytest.mark.parametrize("name", gc.list_presets())
def test_every_preset_uses_the_thesis_law(name):
    veh = gc.load_vehicle(name)
    assert veh.law == "thesis"
    assert not any(k in veh.params for k in ("hd_a", "Cd0", "density", "mass", "volume"))
    if veh.kind == "underwater_glider":
        assert all(k in veh.params for k in THESIS_LIFT_DRAG_KEYS)
        assert veh.density == gc.params.DEFAULT_DENSITY
    # the provenance of a thesis vehicle is the hash it had before laws existed (no 'law' entry)
    doc = {"name": veh.name, "kind": veh.kind, "params": dict(sorted(veh.params.items()))}
    if veh.actuators:
        doc["actuators"] = {k: [str(a.min), str(a.max), str(a.rate), str(a.fixed)]
                            for k, a in sorted(veh.actuators.items())}
    assert veh.provenance == hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()[:16]


UG_PRESETS = [n for n in gc.list_presets() if gc.load_vehicle(n).kind == "underwater_glider"]


@FAST
@given(name=st.sampled_from(UG_PRESETS),
       V=st.lists(st.floats(0.0, 3.0), min_size=1, max_size=6),
       alpha=st.floats(-0.6, 0.6), Omega2=st.floats(-1.0, 1.0))
def test_thesis_lift_drag_is_bitwise_the_thesis_formula(name, V, alpha, Omega2):
    veh = gc.load_vehicle(name)
    V2 = np.asarray(V) ** 2
    p = veh.params
    L_ref = (p["K_L0"] + p["K_L"] * alpha) * V2
    D_ref = (p["K_D0"] + p["K_D"] * alpha * alpha) * V2
    L, D = gc.lift_drag(veh, V2, alpha)
    assert np.array_equal(L, L_ref) and np.array_equal(D, D_ref)
    L2, D2, _ = gc.hydro.loads_at(veh, V2, alpha, Omega2)
    assert np.array_equal(L2, L_ref) and np.array_equal(D2, D_ref)
    # the density argument is ignored by the thesis law (its coefficients hold the density)
    L3, D3 = gc.lift_drag(veh, V2, alpha, density=1000.0)
    assert np.array_equal(L3, L_ref) and np.array_equal(D3, D_ref)


# --------------------------------------------------------------------------------------------- 2. Seaglider law


def test_seaglider_file_loads(seaglider):
    assert seaglider.law == "seaglider"
    for key, value in SG.items():
        assert seaglider.params[key] == value
    assert not any(k in seaglider.params for k in THESIS_LIFT_DRAG_KEYS)
    assert seaglider.density == 1027.0
    assert seaglider.units["hd_b"] == "Pa^(1/4)"


@FAST
@given(V=st.floats(0.05, 1.0), alpha=st.floats(-0.2, 0.2, allow_subnormal=False))
def test_seaglider_lift_drag_closed_form(seaglider, V, alpha):
    q = SG["density"] * V * V / 2
    l2 = SG["length"] ** 2
    a_deg = math.degrees(alpha)
    L_ref = SG["hd_a"] * q * l2 * a_deg
    D_ref = (SG["hd_b"] * q ** (-0.25) + SG["hd_c"] * a_deg**2) * q * l2
    L, D = gc.lift_drag(seaglider, V * V, alpha)
    assert float(L) == pytest.approx(L_ref, rel=1e-13, abs=0.0)
    assert float(D) == pytest.approx(D_ref, rel=1e-13, abs=0.0)
    assert float(D) > 0.0
    # the density argument replaces the file's
    L4, D4 = gc.lift_drag(seaglider, V * V, alpha, density=2 * SG["density"])
    q4 = 2 * q
    assert float(L4) == pytest.approx(SG["hd_a"] * q4 * l2 * a_deg, rel=1e-13, abs=0.0)
    assert float(D4) == pytest.approx((SG["hd_b"] * q4 ** (-0.25) + SG["hd_c"] * a_deg**2) * q4 * l2, rel=1e-13,
                                      abs=0.0)


def _seaglider_glide(theta: float, m0: float, g: float) -> tuple[float, float]:
    """Independent Seaglider steady glide: for given alpha the lift balance gives q, the drag balance is a scalar
    equation in alpha; its first root from zero lift (efficient branch) by a grid scan and brentq."""
    W = m0 * g
    l2 = SG["length"] ** 2

    def q_of(alpha: float) -> float:
        return W * math.cos(theta - alpha) / (SG["hd_a"] * l2 * math.degrees(alpha))

    def f(alpha: float) -> float:
        q = q_of(alpha)
        a_deg = math.degrees(alpha)
        return (SG["hd_b"] * q ** (-0.25) + SG["hd_c"] * a_deg**2) * q * l2 + W * math.sin(theta - alpha)

    sign = math.copysign(1.0, m0)  # heavy: positive lift, alpha > 0
    grid = sign * np.geomspace(1e-9, math.pi / 6, 3000)
    vals = np.array([f(a) for a in grid])
    k = int(np.argmax(vals <= 0))
    assert vals[k] <= 0 < vals[k - 1] and k > 0
    alpha = brentq(f, grid[k - 1], grid[k], xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=500)
    return alpha, math.sqrt(2 * q_of(alpha) / SG["density"])


@st.composite
def pitch_and_heaviness(draw: st.DrawFn) -> tuple[float, float]:
    """Pitch 15-40 degrees of either sign, with a net heaviness of the matching sign (heavy dives nose down)."""
    theta = math.radians(draw(st.floats(15.0, 40.0)))
    m0 = draw(st.floats(0.02, 0.6))
    return (-theta, m0) if draw(st.booleans()) else (theta, -m0)


@settings(max_examples=25, deadline=None)
@given(req=pitch_and_heaviness())
def test_seaglider_steady_flight_closed_form(seaglider, req):
    theta, m0 = req
    alpha_ref, V_ref = _seaglider_glide(theta, m0, seaglider.g)
    sf = gc.steady_flight(seaglider, theta, m0)
    assert bool(sf.feasible)
    assert float(sf.alpha) == pytest.approx(alpha_ref, rel=1e-9, abs=0.0)
    assert float(sf.speed) == pytest.approx(V_ref, rel=1e-9, abs=0.0)
    assert float(sf.gamma) == pytest.approx(theta - alpha_ref, rel=1e-9, abs=0.0)
    assert np.sign(sf.vertical_speed) == -np.sign(m0)  # heavy sinks, light rises


@pytest.mark.parametrize("law", ["thesis", "thesis_asym", "seaglider", "gliderflight"])
@settings(max_examples=30, deadline=None)
@given(reqs=st.lists(pitch_and_heaviness(), min_size=1, max_size=8))
def test_steady_flight_force_balance(seaglider, law, reqs):
    veh = {"thesis": THESIS, "thesis_asym": THESIS_ASYM, "seaglider": seaglider, "gliderflight": GLIDERFLIGHT}[law]
    theta = np.array([r[0] for r in reqs])
    m0 = np.array([r[1] for r in reqs])
    sf = gc.steady_flight(veh, theta, m0)
    assert sf.feasible.all()
    assert np.array_equal(sf.gamma, theta - sf.alpha)
    L, D = gc.lift_drag(veh, sf.speed**2, sf.alpha)
    W = m0 * veh.g
    assert np.all(np.abs(L - W * np.cos(sf.gamma)) <= 1e-12 * np.abs(W))
    assert np.all(np.abs(D + W * np.sin(sf.gamma)) <= 1e-12 * np.abs(W))
    assert np.all(D > 0) and np.all(sf.speed > 0)
    # efficient branch: the lift has the sign of the weight and the angle of attack is on its side of zero lift
    assert np.all(np.sign(L) == np.sign(m0))
    assert np.all(np.sign(sf.alpha - gc.hydro.zero_lift_angle(veh)) == np.sign(m0))
    np.testing.assert_allclose(sf.vertical_speed, sf.speed * np.sin(sf.gamma), rtol=1e-15, atol=0)
    np.testing.assert_allclose(sf.horizontal_speed, sf.speed * np.cos(sf.gamma), rtol=1e-15, atol=0)


# --------------------------------------------------------------------------------------------- 3. gliderflight


@pytest.fixture(scope="module")
def ammonite(tmp_path_factory: pytest.TempPathFactory) -> gc.DiveRecord:
    return gc.read_dive_record(AMMONITE, cache_dir=tmp_path_factory.mktemp("dbdcache"))


def _gliderflight_exact(gm: gfm.SteadyStateGliderModel, depth: np.ndarray, pitch: np.ndarray,
                        volume: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """gliderflight's steady state, its angle of attack solved exactly per sample on its own model_fun."""
    alpha = np.empty_like(pitch)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # fsolve: "xtol too small" once at machine precision
        for i, p in enumerate(pitch):
            a = fsolve(gm.model_fun, abs(p) / 50, args=(abs(p), gm.Cd0), xtol=1e-14)[0]
            assert abs(gm.model_fun(a, abs(p), gm.Cd0)) < 1e-14
            alpha[i] = math.copysign(a, p)
    FB, Fg = gm.compute_FB_and_Fg(depth * 1025 * 9.81, 1025.0, volume)
    U2 = 2 * (FB - Fg) * np.sin(pitch + alpha) / (gm.Cd0 + gm.Cd1 * alpha**2) / 1025.0 / gm.S
    assert np.all(U2 > 0)
    return alpha, np.sqrt(U2)


def test_gliderflight_law_equals_gliderflight(ammonite):
    gm = _gliderflight_model()
    veh = _gliderflight_vehicle(gm)
    assert veh.law == "gliderflight"
    assert gc.hydro.gliderflight_coefficients(veh) == (gm.ah + gm.aw, gm.Cd0, gm.Cd1)
    used = ammonite.mask()
    depth, pitch, vb = ammonite.depth[used], ammonite.pitch[used], ammonite.buoyancy_volume[used]
    # net heaviness: gliderflight's FB - Fg is -m0 g
    FB, Fg = gm.compute_FB_and_Fg(depth * 1025 * 9.81, 1025.0, vb)
    m0 = gc.excess_mass(veh, depth, vb)
    np.testing.assert_allclose(m0 * veh.g, Fg - FB, rtol=1e-12, atol=1e-12)
    sf = gc.steady_flight(veh, pitch, m0)
    assert sf.feasible.all()
    alpha_gf, U_gf = _gliderflight_exact(gm, depth, pitch, vb)
    # gliderflight's glide angle is pitch + alpha: its alpha is minus glidectl's. The issue asks 1e-6; both solve
    # the same balance to rounding (measured 5e-14), so the bound is 1e-10
    np.testing.assert_allclose(sf.alpha, -alpha_gf, rtol=1e-10, atol=0)
    np.testing.assert_allclose(sf.speed, U_gf, rtol=1e-10, atol=0)
    np.testing.assert_allclose(sf.vertical_speed, U_gf * np.sin(pitch + alpha_gf), rtol=1e-10, atol=0)


def test_gliderflight_law_near_gliderflight_solve(ammonite):
    # gliderflight's own solve() interpolates the angle of attack linearly in a 100-point pitch table
    # (SteadyStateGliderModel.pitch_i), about 2e-4 relative off the root of its model_fun: agreement is to 1e-3 only
    gm = _gliderflight_model()
    veh = _gliderflight_vehicle(gm)
    n = len(ammonite)
    data = {"time": np.array(ammonite.time), "pressure": ammonite.depth * 1025 * 9.81 / 1e5,
            "pitch": np.array(ammonite.pitch), "buoyancy_change": ammonite.buoyancy_volume * 1e6,
            "density": np.full(n, 1025.0)}
    res = gm.solve(data)
    used = ammonite.mask()
    sf = gc.predict_flight(veh, ammonite, used)
    np.testing.assert_allclose(sf.speed, res.U[used], rtol=1e-3, atol=0)
    np.testing.assert_allclose(sf.alpha, -res.alpha[used], rtol=1e-3, atol=0)
    # the measured depth rate (gliderflight: ww + w, from its compute_dhdt) is the record's vertical speed
    np.testing.assert_allclose(ammonite.vertical_speed, res.ww + res.w, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(sf.vertical_speed, res.w[used], rtol=1e-3, atol=0)


# --------------------------------------------------------------------------------------------- 4. validation


def _load_error(path: Path) -> str:
    with pytest.raises(gc.VehicleFileError) as info:
        gc.load_vehicle(path)
    return str(info.value)


def _line_number(text: str, prefix: str) -> int:
    hits = [n for n, line in enumerate(text.splitlines(), 1) if line.startswith(prefix)]
    assert len(hits) == 1
    return hits[0]


def test_unknown_law_did_you_mean(tmp_path):
    text = _seaglider_text().replace('law = "seaglider"', 'law = "thesys"')
    msg = _load_error(_write(tmp_path, text))
    assert "did you mean 'thesis'" in msg and "thesys" in msg
    assert f"(line {_line_number(text, 'law = ')})" in msg


def test_key_of_another_law(tmp_path):
    table = """
[hydrodynamics]
law = "gliderflight"
Cd0 = { value = 0.1, unit = "1", source = "test" }
hd_a = { value = 0.003836, unit = "1/deg", source = "test" }
"""
    text = _insert_before_actuators(_without_thesis_lift_drag(SLOCUM_TEXT), table)
    msg = _load_error(_write(tmp_path, text))
    assert "'hd_a'" in msg and "'seaglider'" in msg and "gliderflight" in msg
    assert f"(line {_line_number(text, 'hd_a = ')})" in msg


def test_thesis_key_with_seaglider_law(tmp_path):
    text = re.sub(r"(?m)^(K_L0|K_D0|K_D)\s*=.*\n", "", SLOCUM_TEXT)  # only K_L left of the thesis keys
    text = _insert_before_actuators(text, SEAGLIDER_TABLE)
    msg = _load_error(_write(tmp_path, text))
    assert "'K_L'" in msg and "'thesis'" in msg and "seaglider" in msg


@pytest.mark.parametrize(("good", "bad"), [("K_M0", "K_M0x"), ("mbar", "mbarr")])
def test_misspelled_parameter_did_you_mean_with_line(tmp_path, good, bad):
    text = re.sub(rf"(?m)^{good}(\s*=)", rf"{bad}\1", SLOCUM_TEXT)
    assert text != SLOCUM_TEXT
    msg = _load_error(_write(tmp_path, text))
    assert f"did you mean '{good}'" in msg and bad in msg
    assert f"(line {_line_number(text, bad + ' ')})" in msg


def test_pump_range_in_cm3(tmp_path):
    text = re.sub(r"(?m)^m0   = \{ min = -0\.25,  max = 0\.25,", "m0   = { min = -350, max = 350,", SLOCUM_TEXT)
    assert text != SLOCUM_TEXT
    msg = _load_error(_write(tmp_path, text))
    assert "cm^3" in msg and "'m0'" in msg and "350" in msg


def test_wrong_unit_on_hd_a(tmp_path):
    text = _seaglider_text().replace('unit = "1/deg", source', 'unit = "1/rad", source')
    msg = _load_error(_write(tmp_path, text))
    assert "'hd_a'" in msg and "'1/rad'" in msg and "'1/deg'" in msg
    assert f"(line {_line_number(text, 'hd_a = ')})" in msg


# --------------------------------------------------------------------------------------------- 5. to_toml


def _round_trip(veh: gc.Vehicle, tmp_path: Path) -> gc.Vehicle:
    return gc.load_vehicle(_write(tmp_path, veh.to_toml(), f"{veh.name}_{veh.law}.toml"))


def _assert_same(a: gc.Vehicle, b: gc.Vehicle) -> None:
    assert dict(a.params) == dict(b.params)
    assert a.law == b.law and a.kind == b.kind and a.name == b.name
    assert dict(a.actuators) == dict(b.actuators)
    assert a.provenance == b.provenance


@pytest.mark.parametrize("name", gc.list_presets())
def test_to_toml_round_trip_presets(tmp_path, name):
    veh = gc.load_vehicle(name)
    back = _round_trip(veh, tmp_path)
    _assert_same(veh, back)
    assert back.law == "thesis"
    assert "[hydrodynamics]" not in veh.to_toml()


def test_to_toml_round_trip_other_laws(tmp_path, seaglider):
    sg_hull = seaglider.with_hydrodynamics(mass=52.3, volume=0.051, compressibility=4e-10, thermal_expansion=7e-5,
                                           reference_temperature=12.5)
    for veh in (seaglider, sg_hull, GLIDERFLIGHT, gc.load_vehicle("slocum_shallow").with_hydrodynamics(
            "gliderflight", Cd0=0.15), gc.load_vehicle("rogue").with_hydrodynamics(density=1020.0)):
        back = _round_trip(veh, tmp_path)
        _assert_same(veh, back)
        assert "[hydrodynamics]" in veh.to_toml()


# --------------------------------------------------------------------------------------------- 6. law switching


def test_with_hydrodynamics_switches_law():
    veh = gc.load_vehicle("slocum_shallow")
    sg = veh.with_hydrodynamics("seaglider", **SG)
    assert sg.law == "seaglider"
    assert not any(k in sg.params for k in THESIS_LIFT_DRAG_KEYS)
    assert {k: sg.params[k] for k in SG} == SG
    assert sg.provenance != veh.provenance
    others = {k: v for k, v in veh.params.items() if k not in THESIS_LIFT_DRAG_KEYS}
    assert {k: sg.params[k] for k in others} == others
    with pytest.raises(gc.VehicleFileError, match="hd_a"):
        veh.with_hydrodynamics("seaglider", hd_b=0.01, hd_c=1e-5, length=1.8)  # hd_a missing


@pytest.mark.parametrize("law", ["thesis", "seaglider", "gliderflight"])
@pytest.mark.parametrize("base", ["slocum_shallow", "rogue"])
def test_law_start_matches_at_quarter_metre_per_second(base, law):
    veh = gc.load_vehicle(base)
    start = gc.law_start(veh, law)
    assert start.law == law
    V2 = 0.25**2
    for alpha in (0.0, 0.05, 0.1):
        L0, D0 = gc.lift_drag(veh, V2, alpha)
        L1, D1 = gc.lift_drag(start, V2, alpha)
        assert float(L1) == pytest.approx(float(L0), rel=1e-12, abs=1e-300), (alpha, "lift")
        assert float(D1) == pytest.approx(float(D0), rel=1e-12, abs=0.0), (alpha, "drag")
    back = gc.law_start(start, "thesis")
    assert back.law == "thesis"
    for key in ("K_L", "K_D0", "K_D"):
        assert back.params[key] == pytest.approx(veh.params[key], rel=1e-12), key
    assert back.params["K_L0"] == 0.0 == veh.params["K_L0"]


# --------------------------------------------------------------------------------------------- 7. thesis keys


@pytest.mark.parametrize("key", THESIS_LIFT_DRAG_KEYS)
def test_thesis_keys_of_another_law_raise_model_error(seaglider, key):
    for veh, law in ((seaglider, "seaglider"), (GLIDERFLIGHT, "gliderflight")):
        with pytest.raises(gc.ModelError) as info:
            getattr(veh, key)
        msg = str(info.value)
        assert f"'{law}'" in msg and f"'{key}'" in msg


def test_to_toml_keeps_profile_sources_and_any_text_through_round_trips(tmp_path):
    """A density profile's two sources stay two (they do not double on each round trip), and sources with quotes,
    backslashes, newlines, characters beyond the Basic Multilingual Plane and DEL are written as valid TOML."""
    base = gc.load_vehicle("slocum_shallow").to_toml() + (
        '\n[hydrodynamics]\nlaw = "thesis"\n\n[hydrodynamics.density_profile]\n'
        'depth = { values = [0, 100, 600], unit = "m", source = "CTD cast A" }\n'
        'density = { values = [1024.0, 1026.5, 1027.5], unit = "kg/m^3", source = "CTD cast B" }\n')
    path = tmp_path / "v0.toml"
    path.write_text(base, encoding="utf-8")
    veh = gc.load_vehicle(path).with_hydrodynamics(mass=52.0, source='a "quoted" \\ path\nline two \U0001f41f \x7f')
    assert veh.sources["density_profile.depth"] == "CTD cast A"
    assert veh.sources["density_profile.density"] == "CTD cast B"
    for k in range(3):
        path = tmp_path / f"v{k + 1}.toml"
        path.write_text(veh.to_toml(), encoding="utf-8")
        back = gc.load_vehicle(path)
        assert dict(back.sources) == dict(veh.sources) and back.provenance == veh.provenance
        assert back.density_profile == veh.density_profile
        veh = back


@pytest.mark.parametrize(("extra", "match"), [
    ({"density": 1.025}, "g/cm"),
    ({"mass": 70.0, "volume": 68.4}, "litres"),
    ({"mass": 70.0, "volume": 0.0684, "density": 2000.0}, "not sea water"),
])
def test_hull_values_in_another_unit_are_refused(extra, match):
    with pytest.raises(gc.VehicleFileError, match=match):
        gc.load_vehicle("slocum_shallow").with_hydrodynamics(**extra)


def test_switching_law_drops_the_old_laws_overrides():
    veh = gc.load_vehicle("slocum_shallow", K_D0=3.0)
    sg = gc.law_start(veh, "seaglider")
    assert "K_D0" not in sg.overrides and "K_D0" not in sg.params
