"""Vehicle files: presets, overrides, provenance and the validation errors of ``glidectl.params``."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

import glidectl
from glidectl import GlidectlError, ModelError, VehicleFileError, list_presets, load_vehicle
from glidectl.params import PARAMETER_SPECS

# A minimal valid underwater-glider file (ROGUE numbers, fixed mass model).
HEADER = """\
[vehicle]
name = "testglider"
kind = "{kind}"
title = "test glider"
"""

PARAMS = {
    "g": ("9.81", "m/s^2"),
    "m1": ("13.22", "kg"),
    "m3": ("25.22", "kg"),
    "mbar": ("2.0", "kg"),
    "J2": ("0.1", "kg*m^2"),
    "K_D0": ("18.0", "kg/m"),
    "K_D": ("109.0", "kg/m/rad^2"),
    "K_L0": ("0.0", "kg/m"),
    "K_L": ("306.0", "kg/m/rad"),
    "K_M0": ("0.0", "kg"),
    "K_M": ("-36.5", "kg/rad"),
    "K_q": ("0.0", "kg*s/rad"),
}


def _line(key: str, value: str, unit: str, source: str | None = "test") -> str:
    src = "" if source is None else f', source = "{source}"'
    return f'{key} = {{ value = {value}, unit = "{unit}"{src} }}\n'


def make_toml(*, kind: str = "underwater_glider", drop: tuple[str, ...] = (),
              replace: dict[str, str] | None = None, extra: str = "", no_source: tuple[str, ...] = (),
              units: dict[str, str] | None = None, tail: str = "") -> str:
    replace = replace or {}
    units = units or {}
    text = HEADER.format(kind=kind) + "\n[parameters]\n"
    for key, (value, unit) in PARAMS.items():
        if key in drop:
            continue
        source = None if key in no_source else "test"
        text += _line(key, replace.get(key, value), units.get(key, unit), source)
    return text + extra + tail


def write(tmp_path: Path, text: str, name: str = "veh.toml") -> Path:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def load_error(path: Path, **overrides: float) -> str:
    with pytest.raises(VehicleFileError) as info:
        load_vehicle(path, **overrides)
    return str(info.value)


# --------------------------------------------------------------------------------------------- presets


def test_error_hierarchy():
    for exc in (glidectl.VehicleFileError, glidectl.ModelError, glidectl.InfeasibleGlideError,
                glidectl.SolverError):
        assert issubclass(exc, GlidectlError)
    assert issubclass(VehicleFileError, ValueError)


def test_preset_list_is_the_shipped_files():
    assert set(list_presets()) == {"rogue", "sphere_ch5", "elevator_ch6", "slocum_ch8", "dc8_ctol"}


@pytest.mark.parametrize("name", list_presets())
def test_every_preset_loads_and_is_valid(name):
    veh = load_vehicle(name)
    assert veh.name == name
    assert veh.kind in PARAMETER_SPECS
    spec = PARAMETER_SPECS[veh.kind]
    required = {k for k, s in spec.items() if s.required}
    assert required <= set(veh.params)
    for key, value in veh.params.items():
        assert key in spec
        assert isinstance(value, float) and math.isfinite(value)
        assert veh.sources[key].strip(), f"{name}.{key} has no source"
        assert veh.units[key] == spec[key].unit
        assert getattr(veh, key) == value
    assert re.fullmatch(r"[0-9a-f]{16}", veh.provenance)
    assert load_vehicle(name).provenance == veh.provenance  # deterministic
    assert dict(veh.overrides) == {}
    if veh.kind == "underwater_glider":
        assert veh.mass(1) > 0 and veh.mass(3) > 0
        assert veh.J2 > 0 and veh.mbar >= 0


def test_presets_have_distinct_provenance():
    provs = {load_vehicle(n).provenance for n in list_presets()}
    assert len(provs) == len(list_presets())


def test_load_by_path_equals_preset(tmp_path):
    text = (Path(glidectl.__file__).parent / "vehicles" / "rogue.toml").read_text(encoding="utf-8")
    p = write(tmp_path, text, "rogue_copy.toml")
    veh = load_vehicle(p)
    assert dict(veh.params) == dict(load_vehicle("rogue").params)
    assert veh.provenance == load_vehicle("rogue").provenance  # provenance is about values, not the path
    assert str(p) in veh.path


def test_minimal_file_loads(tmp_path):
    veh = load_vehicle(write(tmp_path, make_toml()))
    assert veh.m1 == 13.22 and veh.K_M == -36.5
    assert veh.mass_model == "fixed"


def test_added_mass_model_depends_on_m0():
    veh = load_vehicle("slocum_ch8")
    assert veh.mass_model == "added"
    # m_i = m + m0 - mbar + m_fi (chapter 8 convention)
    assert veh.mass(1) == pytest.approx(50.0 + 0.25 - 9.0 + 5.0, rel=1e-15)
    assert veh.mass(3, 1.25) == pytest.approx(50.0 + 1.25 - 9.0 + 70.0, rel=1e-15)


# --------------------------------------------------------------------------------------------- overrides


def test_override_changes_value_source_and_provenance():
    base = load_vehicle("sphere_ch5")
    veh = load_vehicle("sphere_ch5", K_M=-100.0)
    assert veh.K_M == -100.0
    assert base.K_M == -50.0  # the original is untouched
    assert veh.sources["K_M"] == "override"
    assert dict(veh.overrides) == {"K_M": -100.0}
    assert veh.provenance != base.provenance
    # every other parameter unchanged
    assert {k: v for k, v in veh.params.items() if k != "K_M"} == {
        k: v for k, v in base.params.items() if k != "K_M"}
    # with_overrides gives the same vehicle, and overriding back restores the provenance
    assert base.with_overrides(K_M=-100.0).provenance == veh.provenance
    assert veh.with_overrides(K_M=-50.0).provenance == base.provenance


def test_override_can_add_an_optional_parameter():
    veh = load_vehicle("rogue", K_beta=20.0)
    assert veh.K_beta == 20.0
    assert veh.has("K_beta") and not load_vehicle("rogue").has("K_beta")


def test_override_unknown_key():
    with pytest.raises(VehicleFileError) as info:
        load_vehicle("rogue", K_bogus=1.0)
    msg = str(info.value)
    assert "K_bogus" in msg and "rogue" in msg


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_override_non_finite(bad):
    with pytest.raises(VehicleFileError) as info:
        load_vehicle("rogue", K_M=bad)
    msg = str(info.value)
    assert "K_M" in msg and "rogue" in msg and "finite" in msg


def test_override_out_of_range():
    with pytest.raises(VehicleFileError, match="J2"):
        load_vehicle("rogue", J2=-0.1)
    with pytest.raises(VehicleFileError, match="J2"):
        load_vehicle("rogue").with_overrides(J2=0.0)


def test_override_non_number():
    with pytest.raises(VehicleFileError, match="K_M"):
        load_vehicle("rogue", K_M="big")  # type: ignore[arg-type]
    with pytest.raises(VehicleFileError, match="K_M"):
        load_vehicle("rogue", K_M=True)


def test_unknown_preset_name():
    with pytest.raises(VehicleFileError) as info:
        load_vehicle("no_such_glider")
    msg = str(info.value)
    assert "no_such_glider" in msg
    assert "rogue" in msg  # lists the presets


def test_missing_file(tmp_path):
    p = tmp_path / "absent.toml"
    with pytest.raises(VehicleFileError) as info:
        load_vehicle(p)
    assert str(p) in str(info.value)


# --------------------------------------------------------------------------------------------- bad files


def _assert_names(msg: str, path: Path, *words: str) -> None:
    assert str(path) in msg, msg
    for w in words:
        assert w in msg, (w, msg)


def test_unknown_parameter_key(tmp_path):
    p = write(tmp_path, make_toml(extra=_line("K_foo", "1.0", "kg")))
    _assert_names(load_error(p), p, "K_foo")


def test_missing_required_key(tmp_path):
    p = write(tmp_path, make_toml(drop=("K_L",)))
    _assert_names(load_error(p), p, "K_L")


def test_wrong_unit(tmp_path):
    p = write(tmp_path, make_toml(units={"K_M": "N*m"}))
    _assert_names(load_error(p), p, "K_M", "N*m", "kg/rad")


def test_equivalent_unit_spellings_accepted(tmp_path):
    # spaces and '.' / '·' for products are normalized
    veh = load_vehicle(write(tmp_path, make_toml(units={"J2": "kg · m^2", "K_q": "kg.s/rad"})))
    assert veh.J2 == 0.1


@pytest.mark.parametrize("bad", ["nan", "inf", "-inf", "+nan"])
def test_non_finite_value(tmp_path, bad):
    p = write(tmp_path, make_toml(replace={"K_D": bad}))
    _assert_names(load_error(p), p, "K_D", "finite")


def test_non_number_value(tmp_path):
    p = write(tmp_path, make_toml(replace={"K_D": '"109"'}))
    _assert_names(load_error(p), p, "K_D")


def test_zero_mass(tmp_path):
    p = write(tmp_path, make_toml(replace={"m1": "0.0"}))
    _assert_names(load_error(p), p, "m1", "> 0")


def test_negative_inertia(tmp_path):
    p = write(tmp_path, make_toml(replace={"J2": "-0.1"}))
    _assert_names(load_error(p), p, "J2")


def test_negative_moving_mass(tmp_path):
    p = write(tmp_path, make_toml(replace={"mbar": "-1.0"}))
    _assert_names(load_error(p), p, "mbar")


def test_missing_source(tmp_path):
    p = write(tmp_path, make_toml(no_source=("K_L",)))
    _assert_names(load_error(p), p, "K_L", "source")


def test_empty_source(tmp_path):
    text = make_toml(drop=("K_L",), extra=_line("K_L", "306.0", "kg/m/rad", source="  "))
    p = write(tmp_path, text)
    _assert_names(load_error(p), p, "K_L", "source")


def test_unknown_top_level_table(tmp_path):
    p = write(tmp_path, make_toml(tail="\n[controller]\ngain = 1.0\n"))
    _assert_names(load_error(p), p, "controller")


def test_unknown_header_key(tmp_path):
    p = write(tmp_path, make_toml().replace('title = "test glider"', 'title = "t"\ncolour = "red"'))
    _assert_names(load_error(p), p, "colour")


def test_invalid_toml_syntax(tmp_path):
    p = write(tmp_path, make_toml() + "K_M = { value = -36.5, unit = \n")
    _assert_names(load_error(p), p, "TOML")


def test_unknown_kind(tmp_path):
    p = write(tmp_path, make_toml(kind="submarine"))
    _assert_names(load_error(p), p, "kind", "submarine")


def test_both_mass_models(tmp_path):
    p = write(tmp_path, make_toml(extra=_line("m", "28.0", "kg") + _line("m0", "0.5", "kg")))
    _assert_names(load_error(p), p, "m1", "'m'")


def test_no_mass_model(tmp_path):
    p = write(tmp_path, make_toml(drop=("m1", "m3")))
    _assert_names(load_error(p), p, "m1", "'m'")


def test_fixed_mass_model_needs_m1_and_m3(tmp_path):
    p = write(tmp_path, make_toml(drop=("m3",)))
    _assert_names(load_error(p), p, "m3")


def test_added_mass_model_needs_m0(tmp_path):
    extra = _line("m", "28.0", "kg") + _line("m_f1", "0.0", "kg") + _line("m_f3", "0.0", "kg")
    p = write(tmp_path, make_toml(drop=("m1", "m3"), extra=extra))
    _assert_names(load_error(p), p, "m0")
    veh = load_vehicle(p, m0=0.5)  # supplying it as an override fixes the file
    assert veh.mass(1) == pytest.approx(28.0 + 0.5 - 2.0, rel=1e-15)


def test_parameter_entry_must_be_inline_table(tmp_path):
    p = write(tmp_path, make_toml(drop=("K_L",), extra="K_L = 306.0\n"))
    _assert_names(load_error(p), p, "K_L")


def test_errors_are_glidectl_errors(tmp_path):
    p = write(tmp_path, make_toml(drop=("K_L",)))
    with pytest.raises(GlidectlError):
        load_vehicle(p)


# --------------------------------------------------------------------------------------------- attributes


def test_undefined_optional_parameter_is_model_error():
    veh = load_vehicle("rogue")
    with pytest.raises(ModelError) as info:
        _ = veh.K_beta
    msg = str(info.value)
    assert "K_beta" in msg and "rogue" in msg


def test_unknown_attribute_is_attribute_error():
    veh = load_vehicle("rogue")
    with pytest.raises(AttributeError):
        _ = veh.not_a_parameter
    assert not hasattr(veh, "not_a_parameter")


def test_vehicle_is_immutable():
    veh = load_vehicle("rogue")
    with pytest.raises((AttributeError, TypeError)):
        veh.name = "other"  # type: ignore[misc]
    with pytest.raises(TypeError):
        veh.params["K_M"] = 0.0  # type: ignore[index]


def test_vehicle_pickles_and_deep_copies():
    """Vehicles must cross process boundaries (docs/conventions.md: sweeps take any concurrent.futures.Executor, e.g. a
    ProcessPoolExecutor, which pickles its arguments) and survive copy.deepcopy."""
    import copy
    import pickle

    veh = load_vehicle("rogue", K_M=-40.0)
    for clone in (pickle.loads(pickle.dumps(veh)), copy.deepcopy(veh)):
        assert clone == veh
        assert dict(clone.params) == dict(veh.params)
        assert clone.provenance == veh.provenance
        assert dict(clone.overrides) == {"K_M": -40.0}
        with pytest.raises(ModelError):
            _ = clone.K_beta
