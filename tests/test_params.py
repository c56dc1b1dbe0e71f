"""Vehicle files: presets, overrides, provenance and the validation errors of ``glidectl.params``."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

import glidectl
import glidectl.errors as gc_errors
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
    assert set(list_presets()) == {"rogue", "sphere_ch5", "elevator_ch6", "slocum_ch8", "dc8_ctol", "slocum_shallow"}


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


# ------------------------------------------------------------------------------ issue 15: clear errors


def test_file_that_is_not_utf8_is_a_vehicle_file_error(tmp_path):
    p = tmp_path / "latin1.toml"
    p.write_bytes(make_toml().replace("test glider", "t\xe9st glider").encode("latin-1"))
    msg = load_error(p)
    assert "UTF-8" in msg and str(p) in msg
    p.write_bytes(b"\xff\xfe[vehicle]\n")
    assert "UTF-8" in load_error(p)


@pytest.mark.parametrize("bad", [None, 3, 2.5, b"rogue", ["rogue"]])
def test_name_or_path_of_the_wrong_type(bad):
    with pytest.raises(gc_errors.ArgumentTypeError, match="name_or_path"):
        load_vehicle(bad)
    with pytest.raises(TypeError):  # also a TypeError
        load_vehicle(bad)


def test_empty_name_is_not_a_preset():
    with pytest.raises(VehicleFileError, match="no preset or file named ''"):
        load_vehicle("")


def test_directory_and_device_are_not_vehicle_files(tmp_path):
    d = tmp_path / "dir.toml"
    d.mkdir()
    assert "not a regular file" in load_error(d)
    if Path("/dev/zero").exists():  # reading it would never end
        assert "not a regular file" in load_error(Path("/dev/zero"))


def test_path_with_a_nul_byte(tmp_path):
    with pytest.raises(VehicleFileError, match="cannot read"):
        load_vehicle(str(tmp_path / "a\x00b.toml"))


def test_oversized_file_is_refused_before_parsing(tmp_path):
    from glidectl.params import MAX_FILE_BYTES

    p = write(tmp_path, make_toml() + "#" * (MAX_FILE_BYTES + 10))
    assert "larger than" in load_error(p)


def test_deeply_nested_toml_is_a_vehicle_file_error(tmp_path):
    depth = 50_000
    p = write(tmp_path, make_toml(extra=f"x = {'[' * depth}{']' * depth}\n"))
    with pytest.raises(VehicleFileError):
        load_vehicle(p)


@pytest.mark.parametrize("snippet", ["x = ", "[parameters\n", "g = { value = 1, unit = }\n", "\x00"])
def test_bad_toml_is_a_vehicle_file_error(tmp_path, snippet):
    p = write(tmp_path, make_toml(tail=snippet))
    with pytest.raises(VehicleFileError):
        load_vehicle(p)


@pytest.mark.parametrize("entry", ['{ value = 13.0, unit = 3, source = "t" }',
                                   '{ value = 13.0, unit = "kg", source = ["t"] }',
                                   '{ value = 13.0, unit = "kg", source = "t", note = 1.0 }'])
def test_entry_strings_must_be_strings(tmp_path, entry):
    p = write(tmp_path, make_toml(extra=f"m2 = {entry}\n"))
    with pytest.raises(VehicleFileError, match="must be strings"):
        load_vehicle(p)


def test_header_title_must_be_a_string(tmp_path):
    p = write(tmp_path, make_toml().replace('title = "test glider"', "title = 3"))
    assert "'title' must be a string" in load_error(p)


@pytest.mark.parametrize("value", [np.float64(-90.0), np.float32(-90.0), np.int64(-90), np.array(-90.0)])
def test_numpy_real_overrides_are_accepted(value):
    veh = load_vehicle("rogue", K_M=value)
    assert veh.K_M == -90.0 and isinstance(veh.K_M, float)
    assert isinstance(veh.overrides["K_M"], float)


@pytest.mark.parametrize("value", ["-90", None, True, np.bool_(True), 1j, [1.0], np.array([1.0]), {"value": 1.0}])
def test_override_of_the_wrong_type_is_refused(value):
    with pytest.raises(VehicleFileError, match="must be a real number"):
        load_vehicle("rogue", K_M=value)


@pytest.mark.parametrize("kw", [{"K_M": 1e13}, {"m1": 1e-13}, {"J2": 1e-300}, {"g": 1e300}])
def test_override_beyond_the_plausibility_limits(kw):
    with pytest.raises(VehicleFileError, match="plausibility limit"):
        load_vehicle("rogue", **kw)


def test_file_value_beyond_the_plausibility_limits(tmp_path):
    assert "plausibility limit" in load_error(write(tmp_path, make_toml(replace={"K_D0": "1e300"})))


def test_with_overrides_follows_the_same_rules():
    rogue = load_vehicle("rogue")
    with pytest.raises(VehicleFileError):
        rogue.with_overrides(K_M="x")
    with pytest.raises(VehicleFileError):
        rogue.with_overrides(bogus=1.0)
    assert rogue.with_overrides(K_M=np.float32(-1.0)).K_M == -1.0


def test_direct_construction_is_validated():
    good = load_vehicle("rogue")
    kw = dict(name="x", kind="underwater_glider", title="x", params=dict(good.params), sources={}, path="x.toml")
    assert dict(glidectl.Vehicle(**kw).params) == dict(good.params)  # valid parameters pass
    with pytest.raises(VehicleFileError, match="unknown parameter"):
        glidectl.Vehicle(**{**kw, "params": {**good.params, "bogus": 1.0}})
    with pytest.raises(VehicleFileError, match="finite"):
        glidectl.Vehicle(**{**kw, "params": {**good.params, "K_M": math.nan}})
    with pytest.raises(VehicleFileError, match="missing required"):
        glidectl.Vehicle(**{**kw, "params": {"g": 9.81}})
    with pytest.raises(VehicleFileError, match="unknown vehicle kind"):
        glidectl.Vehicle(**{**kw, "kind": "blimp"})
    with pytest.raises(gc_errors.ArgumentTypeError):
        glidectl.Vehicle(**{**kw, "params": None})
    with pytest.raises(gc_errors.ArgumentTypeError):
        glidectl.Vehicle(**{**kw, "name": 3})


def test_mass_and_has_check_their_arguments():
    slocum = load_vehicle("slocum_ch8")
    assert slocum.mass(1) == pytest.approx(slocum.m + slocum.m0 - slocum.mbar + slocum.m_f1)
    assert slocum.mass(np.int64(2), np.array([0.1, 0.2])).shape == (2,)
    with pytest.raises(gc_errors.ArgumentError, match="axis"):
        slocum.mass(7)
    for bad in (0, 4, -1):  # plain ints outside 1..3 leave the fast path and are refused
        with pytest.raises(gc_errors.ArgumentError, match="axis"):
            slocum.mass(bad)
    assert slocum.mass(3, np.float64(0.125)) == slocum.mass(3, 0.125) == slocum.m + 0.125 - slocum.mbar + slocum.m_f3
    with pytest.raises(gc_errors.ArgumentTypeError, match="m0"):
        slocum.mass(1, np.True_)
    with pytest.raises(gc_errors.ArgumentTypeError, match="axis"):
        slocum.mass("1")
    with pytest.raises(gc_errors.ArgumentTypeError, match="axis"):
        slocum.mass(True)
    with pytest.raises(gc_errors.ArgumentTypeError, match="m0"):
        slocum.mass(1, "0.3")
    with pytest.raises(ModelError, match="mass m"):
        load_vehicle("dc8_ctol").mass(1)
    with pytest.raises(gc_errors.ArgumentTypeError):
        slocum.has(3)
    assert slocum.has("m", "m0") and not slocum.has("m1")


def test_the_file_source_is_kept_written_back_and_outside_the_hash():
    import tomllib

    veh = load_vehicle("slocum_shallow")
    assert veh.source.startswith("Graver 2005") and veh.source == veh.sources[glidectl.params.FILE_SOURCE_KEY]
    assert tomllib.loads(veh.to_toml())["vehicle"]["source"] == veh.source
    assert veh.provenance == "04e92c2da1639da3"           # the file source is provenance of the text, not the values
    assert load_vehicle("slocum_shallow", K_M=-90.0).source == veh.source
