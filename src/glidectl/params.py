"""Vehicle parameters: TOML files, validation, frozen :class:`Vehicle` objects with provenance.

A vehicle file is TOML with a ``[vehicle]`` header and a ``[parameters]`` table whose entries are inline tables
``key = { value = ..., unit = "...", source = "..." }``. Every key must be known for the vehicle ``kind``, carry the
exact unit glidectl expects (SI; angles in rad) and cite its source. Loading refuses unknown and missing keys,
wrong units, non-finite values and non-positive masses or inertias, naming the key and the file.

Mass models (underwater gliders)
--------------------------------
Two ways to give the body-frame mass matrix ``M = diag(m1, m2, m3)`` of §2.2.2 are accepted:

* ``fixed``: ``m1, m3`` (and ``m2`` for 3D work) are given directly, as for ROGUE (§2.3.1).
* ``added``: ``m`` (mass of displaced fluid) and added masses ``m_f1, m_f2, m_f3``; then, with
  ``m_s = m_h + m_b = m + m0 - mbar`` (docs/conventions.md, chapter 8 convention), ``M = m_s I + diag(m_f)``
  depends on the buoyancy ``m0``. This is the convention of Table 8.1 and of §6.3 (``m = m1 - m0 = m3 - m0``).
"""

from __future__ import annotations

import hashlib
import json
import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from types import MappingProxyType
from typing import Any, Literal

from .errors import ModelError, VehicleFileError

__all__ = ["PARAMETER_SPECS", "ParamSpec", "Vehicle", "list_presets", "load_vehicle"]

Constraint = Literal["positive", "nonnegative", "any"]


@dataclass(frozen=True)
class ParamSpec:
    """Specification of one vehicle parameter: unit, meaning, sign constraint and where it is used."""

    unit: str
    description: str
    constraint: Constraint = "any"
    required: bool = False


_UG: dict[str, ParamSpec] = {
    "g": ParamSpec("m/s^2", "gravitational acceleration", "positive", True),
    # --- mass model 'fixed'
    "m1": ParamSpec("kg", "total mass (body + added) along body-1, M = diag(m1, m2, m3) (2.2.2)", "positive"),
    "m2": ParamSpec("kg", "total mass (body + added) along body-2", "positive"),
    "m3": ParamSpec("kg", "total mass (body + added) along body-3", "positive"),
    # --- mass model 'added'
    "m": ParamSpec("kg", "mass of displaced fluid (chapter 8 convention)", "positive"),
    "m_h": ParamSpec("kg", "hull mass", "positive"),
    "m_f1": ParamSpec("kg", "added mass along body-1", "nonnegative"),
    "m_f2": ParamSpec("kg", "added mass along body-2", "nonnegative"),
    "m_f3": ParamSpec("kg", "added mass along body-3", "nonnegative"),
    # --- internal moving mass and inertia
    "mbar": ParamSpec("kg", "internal moving point mass (0: no moving mass)", "nonnegative", True),
    "J1": ParamSpec("kg*m^2", "total inertia about body-1", "positive"),
    "J2": ParamSpec("kg*m^2", "total inertia about body-2 (J_s + J_f)", "positive", True),
    "J3": ParamSpec("kg*m^2", "total inertia about body-3", "positive"),
    # --- hydrodynamics (2.9)-(2.14)
    "K_D0": ParamSpec("kg/m", "zero-incidence drag coefficient (2.9)", "nonnegative", True),
    "K_D": ParamSpec("kg/m/rad^2", "induced drag coefficient (2.9)", "nonnegative", True),
    "K_L0": ParamSpec("kg/m", "zero-incidence lift coefficient (2.11)", "any", True),
    "K_L": ParamSpec("kg/m/rad", "lift slope (2.11)", "positive", True),
    "K_M0": ParamSpec("kg", "zero-incidence pitching moment coefficient (2.13)", "any", True),
    "K_M": ParamSpec("kg/rad", "pitching moment slope (2.13)", "any", True),
    "K_q": ParamSpec("kg*s/rad", "pitch damping K_q2 of (2.13)", "any", True),
    "K_beta": ParamSpec("kg/m/rad", "side-force slope (2.10)", "any"),
    "K_MR": ParamSpec("kg/rad", "rolling moment due to sideslip (2.12)", "any"),
    "K_MY": ParamSpec("kg/rad", "yawing moment due to sideslip (2.14)", "any"),
    "K_q1": ParamSpec("kg*s/rad", "roll damping of (2.12)", "any"),
    "K_q3": ParamSpec("kg*s/rad", "yaw damping of (2.14)", "any"),
    "K_Omega1_1": ParamSpec("kg*m^2*s/rad", "chapter 8 linear roll damping (no V^2)", "any"),
    "K_Omega1_2": ParamSpec("kg*m^2*s/rad", "chapter 8 linear pitch damping (no V^2)", "any"),
    "K_Omega1_3": ParamSpec("kg*m^2*s/rad", "chapter 8 linear yaw damping (no V^2)", "any"),
    "K_Omega2_1": ParamSpec("kg*m^2*s^2/rad^2", "chapter 8 quadratic roll damping", "any"),
    "K_Omega2_2": ParamSpec("kg*m^2*s^2/rad^2", "chapter 8 quadratic pitch damping", "any"),
    "K_Omega2_3": ParamSpec("kg*m^2*s^2/rad^2", "chapter 8 quadratic yaw damping", "any"),
    # --- elevator (§6.3) and actuator limits
    "delta": ParamSpec("kg/m/rad", "elevator moment-to-force coupling factor (§6.3)", "nonnegative"),
    "u2_max": ParamSpec("rad", "elevator (control angle of attack) saturation", "positive"),
    "u4_max": ParamSpec("kg/s", "buoyancy pump rate limit |u4| <= u4_max", "positive"),
    "m0_max": ParamSpec("kg", "buoyancy range |m0| <= m0_max", "positive"),
    # --- nominal operating point (optional; studies may use it as a default)
    "m0": ParamSpec("kg", "nominal net buoyancy (heaviness) m0", "any"),
    "r_P1": ParamSpec("m", "nominal moving-mass position, body-1", "any"),
    "r_P2": ParamSpec("m", "nominal moving-mass position, body-2", "any"),
    "r_P3": ParamSpec("m", "nominal moving-mass position, body-3", "any"),
}

_CTOL: dict[str, ParamSpec] = {
    "a_L": ParamSpec("1", "lift coefficient (7.1)", "positive", True),
    "a_D": ParamSpec("1", "drag coefficient (7.2)", "positive", True),
    "b": ParamSpec("1", "drag polar coefficient (7.2)", "nonnegative", True),
    "c": ParamSpec("1", "lift slope ratio (7.1)", "positive", True),
    "epsilon": ParamSpec("1", "elevator moment-to-force coupling (7.5)-(7.6)", "nonnegative", True),
    "rho_AW_half": ParamSpec("kg/m", "rho A_W / 2, normalized to 1 in §7.1", "positive", True),
    "m": ParamSpec("kg", "aircraft mass, normalized to 1 in §7.1", "positive", True),
    "g": ParamSpec("m/s^2", "gravity, normalized to 1 in §7.1", "positive", True),
    "J": ParamSpec("kg*m^2", "pitch inertia, normalized to 1 in §7.1", "positive", True),
    "m_physical": ParamSpec("kg", "physical DC-8 mass quoted in §7.3.3 (not in the normalized model)", "positive"),
    "J2_physical": ParamSpec("kg*m^2", "physical DC-8 pitch inertia quoted in §7.3.3", "positive"),
}

PARAMETER_SPECS: Mapping[str, Mapping[str, ParamSpec]] = MappingProxyType(
    {"underwater_glider": MappingProxyType(_UG), "ctol": MappingProxyType(_CTOL)}
)

_HEADER_KEYS = {"name", "kind", "title", "source", "notes"}


def _norm_unit(u: str) -> str:
    return u.replace(" ", "").replace(".", "*").replace("·", "*")


@dataclass(frozen=True)
class Vehicle:
    """A validated, immutable vehicle description.

    Parameters are reached as attributes (``veh.m1``, ``veh.K_M``) or through :attr:`params`. ``provenance`` is
    a SHA-256 of the canonical parameter set (file values plus overrides), carried by every result computed from
    this vehicle.

    Attributes
    ----------
    name, kind, title : str
        Preset name, ``"underwater_glider"`` or ``"ctol"``, human title.
    params : Mapping[str, float]
        Parameter values in SI units (angles in rad).
    sources : Mapping[str, str]
        Source of each value (thesis section/table, or ``"override"``).
    path : str
        File the vehicle was read from.
    overrides : Mapping[str, float]
        Values that replaced the file's.
    """

    name: str
    kind: str
    title: str
    params: Mapping[str, float]
    sources: Mapping[str, str]
    path: str
    overrides: Mapping[str, float] = field(default_factory=lambda: MappingProxyType({}))
    notes: str = ""

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        # mappingproxy fields do not pickle; rebuild from plain dicts (used by pickle, copy and multiprocessing)
        return (_vehicle_from_plain, (self.name, self.kind, self.title, dict(self.params), dict(self.sources),
                                      self.path, dict(self.overrides), self.notes))

    def __getattr__(self, key: str) -> float:
        params = object.__getattribute__(self, "params")
        if key in params:
            return params[key]
        spec = PARAMETER_SPECS.get(object.__getattribute__(self, "kind"), {})
        if key in spec:
            raise ModelError(
                f"vehicle '{object.__getattribute__(self, 'name')}' does not define '{key}' "
                f"({spec[key].description}); add it to {object.__getattribute__(self, 'path')} "
                f"or pass it as an override: load_vehicle(..., {key}=...)"
            )
        raise AttributeError(key)

    @property
    def units(self) -> Mapping[str, str]:
        """Unit of each parameter (as in the vehicle file)."""
        spec = PARAMETER_SPECS[self.kind]
        return MappingProxyType({k: spec[k].unit for k in self.params})

    @property
    def provenance(self) -> str:
        """SHA-256 (first 16 hex digits) of name, kind and the canonical parameter values."""
        blob = json.dumps({"name": self.name, "kind": self.kind, "params": dict(sorted(self.params.items()))},
                          sort_keys=True)
        return hashlib.sha256(blob.encode()).hexdigest()[:16]

    def has(self, *keys: str) -> bool:
        """True when every key in ``keys`` is defined."""
        return all(k in self.params for k in keys)

    @property
    def mass_model(self) -> str:
        """``"fixed"`` (m1, m3 given) or ``"added"`` (M depends on m0 through m_s = m + m0 - mbar)."""
        return "fixed" if "m1" in self.params else "added"

    def mass(self, axis: int, m0: Any = None) -> Any:
        """Total mass ``m_i`` along body axis ``axis`` (1, 2 or 3), in kg.

        Parameters
        ----------
        axis : int
            Body axis 1, 2 or 3.
        m0 : float or array, optional
            Net buoyancy (kg); needed only for the ``added`` mass model, where
            ``m_i = m + m0 - mbar + m_fi`` (§2.2.2 with the chapter 8 convention of docs/conventions.md).
        """
        p = self.params
        if self.mass_model == "fixed":
            key = f"m{axis}"
            if key not in p:
                return getattr(self, key)  # raises ModelError naming the key
            return p[key]
        if m0 is None:
            m0 = self.m0
        return p["m"] + m0 - p["mbar"] + p.get(f"m_f{axis}", 0.0)

    def with_overrides(self, **overrides: float) -> Vehicle:
        """Return a new validated vehicle with some parameters replaced (same rules as the file)."""
        return _build_vehicle(self.name, self.kind, self.title, dict(self.params), dict(self.sources),
                              self.path, {**self.overrides, **overrides}, self.notes, overrides)

    def summary_rows(self) -> list[tuple[str, str, str, str]]:
        """(key, value, unit, source) rows for reports."""
        spec = PARAMETER_SPECS[self.kind]
        return [(k, f"{v:.6g}", spec[k].unit, self.sources.get(k, "")) for k, v in self.params.items()]


def _presets_dir() -> Any:
    return resources.files("glidectl") / "vehicles"


def list_presets() -> list[str]:
    """Names of the vehicle presets shipped with glidectl.

    Returns
    -------
    list of str
        Sorted preset names (the ``.toml`` files of ``glidectl/vehicles``), each accepted by :func:`load_vehicle`.

    Raises
    ------
    OSError
        If the package's ``vehicles`` folder cannot be listed (a broken installation).
    """
    return sorted(p.name[:-5] for p in _presets_dir().iterdir() if p.name.endswith(".toml"))


def _check_value(key: str, value: Any, spec: ParamSpec, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise VehicleFileError(f"{where}: parameter '{key}' must be a number, got {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise VehicleFileError(f"{where}: parameter '{key}' must be finite, got {value!r}")
    if spec.constraint == "positive" and not v > 0:
        raise VehicleFileError(f"{where}: parameter '{key}' ({spec.description}) must be > 0, got {v:g}")
    if spec.constraint == "nonnegative" and not v >= 0:
        raise VehicleFileError(f"{where}: parameter '{key}' ({spec.description}) must be >= 0, got {v:g}")
    return v


def _vehicle_from_plain(name: str, kind: str, title: str, params: dict[str, float], sources: dict[str, str],
                        path: str, overrides: dict[str, float], notes: str) -> Vehicle:
    return Vehicle(name=name, kind=kind, title=title, params=MappingProxyType(params),
                   sources=MappingProxyType(sources), path=path, overrides=MappingProxyType(overrides),
                   notes=notes)


def _build_vehicle(name: str, kind: str, title: str, values: dict[str, float], sources: dict[str, str],
                   path: str, all_overrides: dict[str, float], notes: str,
                   new_overrides: Mapping[str, float]) -> Vehicle:
    spec = PARAMETER_SPECS[kind]
    for key, val in new_overrides.items():
        if key not in spec:
            raise VehicleFileError(
                f"override '{key}' is not a parameter of a {kind} vehicle ({path}); known: {', '.join(spec)}")
        values[key] = _check_value(key, val, spec[key], f"override for {path}")
        sources[key] = "override"
    missing = [k for k, s in spec.items() if s.required and k not in values]
    if missing:
        raise VehicleFileError(f"{path}: missing required parameter(s) {', '.join(missing)} for a {kind} vehicle")
    if kind == "underwater_glider":
        fixed = "m1" in values or "m3" in values
        added = "m" in values
        if fixed == added:
            raise VehicleFileError(
                f"{path}: give exactly one mass model: either 'm1' and 'm3' (fixed total masses) or 'm' "
                "(displaced-fluid mass) with added masses 'm_f1', 'm_f3'")
        if fixed and not ("m1" in values and "m3" in values):
            raise VehicleFileError(f"{path}: the fixed mass model needs both 'm1' and 'm3'")
        if added:
            if "m0" not in values:
                raise VehicleFileError(f"{path}: the 'added' mass model needs a nominal 'm0'")
            if values["m"] + values["m0"] - values["mbar"] <= 0:
                raise VehicleFileError(f"{path}: stationary mass m + m0 - mbar must be > 0")
        if "m_h" in values and "m" in values and "m0" in values:
            m_b = values["m0"] + values["m"] - values["m_h"] - values["mbar"]
            if m_b < 0:
                raise VehicleFileError(
                    f"{path}: buoyancy mass m_b = m0 + m - m_h - mbar = {m_b:g} kg is negative")
    return Vehicle(name=name, kind=kind, title=title, params=MappingProxyType(dict(values)),
                   sources=MappingProxyType(dict(sources)), path=path,
                   overrides=MappingProxyType(dict(all_overrides)), notes=notes)


def _parse(text: str, where: str) -> tuple[str, str, str, str, dict[str, float], dict[str, str]]:
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise VehicleFileError(f"{where}: not valid TOML: {exc}") from None
    unknown_top = set(doc) - {"vehicle", "parameters"}
    if unknown_top:
        raise VehicleFileError(f"{where}: unknown top-level table(s) {sorted(unknown_top)}; "
                               "expected [vehicle] and [parameters]")
    head = doc.get("vehicle")
    if not isinstance(head, dict):
        raise VehicleFileError(f"{where}: missing [vehicle] table")
    bad = set(head) - _HEADER_KEYS
    if bad:
        raise VehicleFileError(f"{where}: unknown key(s) {sorted(bad)} in [vehicle]; allowed: {sorted(_HEADER_KEYS)}")
    for k in ("name", "kind"):
        if not isinstance(head.get(k), str):
            raise VehicleFileError(f"{where}: [vehicle] needs a string '{k}'")
    kind = head["kind"]
    if kind not in PARAMETER_SPECS:
        raise VehicleFileError(f"{where}: unknown vehicle kind '{kind}'; expected one of {sorted(PARAMETER_SPECS)}")
    spec = PARAMETER_SPECS[kind]
    table = doc.get("parameters")
    if not isinstance(table, dict):
        raise VehicleFileError(f"{where}: missing [parameters] table")
    values: dict[str, float] = {}
    sources: dict[str, str] = {}
    for key, entry in table.items():
        if key not in spec:
            raise VehicleFileError(
                f"{where}: unknown parameter '{key}' for a {kind} vehicle; known: {', '.join(spec)}")
        if not isinstance(entry, dict) or set(entry) - {"value", "unit", "source", "note"} or not {
                "value", "unit", "source"} <= set(entry):
            raise VehicleFileError(
                f"{where}: parameter '{key}' must be an inline table {{ value = ..., unit = \"...\", "
                f"source = \"...\" }} (optional 'note'), got {entry!r}")
        unit = str(entry["unit"])
        if _norm_unit(unit) != _norm_unit(spec[key].unit):
            raise VehicleFileError(
                f"{where}: parameter '{key}' has unit '{unit}', glidectl expects '{spec[key].unit}' "
                "(SI, angles in rad): convert the value")
        if not str(entry["source"]).strip():
            raise VehicleFileError(f"{where}: parameter '{key}' needs a non-empty 'source'")
        values[key] = _check_value(key, entry["value"], spec[key], where)
        sources[key] = str(entry["source"])
    return head["name"], kind, str(head.get("title", head["name"])), str(head.get("notes", "")), values, sources


def load_vehicle(name_or_path: str | Path, **overrides: float) -> Vehicle:
    """Load a vehicle preset or TOML file, validate it, and apply overrides.

    Parameters
    ----------
    name_or_path : str or Path
        A preset name (see :func:`list_presets`: ``"rogue"``, ``"sphere_ch5"``, ...) or a path to a TOML file.
    **overrides : float
        Parameter values replacing the file's (SI units), validated like the file, e.g. ``K_M=-100.0``.

    Returns
    -------
    Vehicle

    Raises
    ------
    VehicleFileError
        Unknown preset, unreadable file, unknown/missing keys, wrong units, non-finite or out-of-range values.
    """
    s = str(name_or_path)
    if s in list_presets():
        res = _presets_dir() / f"{s}.toml"
        text, where = res.read_text(encoding="utf-8"), f"preset '{s}'"
    else:
        p = Path(s)
        if not p.suffix and not p.exists():
            raise VehicleFileError(f"no preset or file named '{s}'; presets: {', '.join(list_presets())}")
        try:
            text = p.read_text(encoding="utf-8")
        except OSError as exc:
            raise VehicleFileError(f"cannot read vehicle file '{p}': {exc.strerror}") from None
        where = str(p)
    name, kind, title, notes, values, sources = _parse(text, where)
    return _build_vehicle(name, kind, title, values, sources, where, dict(overrides), notes, overrides)
