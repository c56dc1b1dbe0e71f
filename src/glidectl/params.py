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

Actuators
---------
An optional ``[actuators]`` table gives the range and rate of what the vehicle can move in flight::

    [actuators]
    m0   = { min = -0.25, max = 0.25, rate = 0.01, unit = "kg", source = "..." }     # buoyancy pump
    r_P1 = { min = -0.025, max = 0.025, rate = 0.005, unit = "m", source = "..." }  # moving mass along the hull
    r_P3 = { fixed = 0.035, unit = "m", source = "..." }                             # not actuated

Keys are those of :data:`ACTUATOR_SPECS`; rates are in unit/s; a missing ``rate`` means no rate limit. Every
function that picks or commands an actuator setting respects these limits. The earlier parameters ``u2_max``,
``u4_max`` and ``m0_max`` moved into this table (``elevator``, ``m0`` rate, ``m0`` range).

Uncertainty
-----------
An optional ``[uncertainty]`` table says how well some coefficients are known, one inline table per key of
``veh.params``: an interval ``K_M = { min = -60.0, max = -40.0, source = "..." }`` or ``{ rel = 0.3, source = "..." }``
(``nominal -+ |nominal| * 0.3``), a normal ``{ std = 2.0, source = "..." }`` or ``{ rel_std = 0.3, source = "..." }``
(optionally truncated with ``min``/``max``), and correlations between normal entries in
``[uncertainty.correlation]`` (``"K_L,K_D" = 0.6``). :mod:`glidectl.uncertainty` describes the rules;
:meth:`Vehicle.sample` and :meth:`Vehicle.vertices` draw vehicles from it.

Plausibility limits
-------------------
A vehicle file is read only if it is a regular file of at most :data:`MAX_FILE_BYTES` (1 MiB) of UTF-8 TOML. Every
value (from the file or an override) must be a finite real number with ``|value| <=`` :data:`VALUE_MAX` (1e12, SI
units); a parameter that must be positive (masses, inertias, ``g``, ``K_L``...) must also be ``>=``
:data:`POSITIVE_MIN` (1e-12), so that no later division overflows.
"""

from __future__ import annotations

import difflib
import hashlib
import json
import math
import numbers
import os
import re
import tomllib
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from types import MappingProxyType
from typing import Any, Literal

import numpy as np

from .checks import integer
from .errors import ArgumentError, ArgumentTypeError, ModelError, VehicleFileError
from .uncertainty import Uncertainty, check_uncertainty, draw_values, keep_contained, vertex_values

__all__ = [
    "ACTUATOR_SPECS",
    "DEFAULT_DENSITY",
    "DENSITY_RANGE",
    "FILE_SOURCE_KEY",
    "GLIDERFLIGHT_DEFAULTS",
    "HULL_MASS_RATIO",
    "HYDRO_SPECS",
    "MAX_FILE_BYTES",
    "PARAMETER_SPECS",
    "POSITIVE_MIN",
    "PUMP_FRACTION_MAX",
    "THESIS_LIFT_DRAG_KEYS",
    "VALUE_MAX",
    "Actuator",
    "ActuatorSpec",
    "ParamSpec",
    "StackedVehicle",
    "Vehicle",
    "VehicleSample",
    "list_presets",
    "load_vehicle",
    "stack_vehicles",
]

#: Key of :attr:`Vehicle.sources` holding the file's ``[vehicle] source`` (not a parameter name).
FILE_SOURCE_KEY = "[vehicle]"
#: Largest vehicle file read (bytes): vehicle files are a few kB; anything larger is refused before parsing.
MAX_FILE_BYTES = 1 << 20
#: Plausibility limit on the magnitude of every parameter value (SI units).
VALUE_MAX = 1e12
#: Smallest value of a parameter that must be positive (masses, inertias, g, lift slopes...).
POSITIVE_MIN = 1e-12

Constraint = Literal["positive", "nonnegative", "any"]


@dataclass(frozen=True)
class ParamSpec:
    """Specification of one vehicle parameter: unit, meaning, sign constraint and where it is used.

    Attributes
    ----------
    unit : str
        The unit the vehicle file must state (SI, angles in rad).
    description : str
        What the parameter is, with the thesis equation.
    constraint : {"positive", "nonnegative", "any"}
        Sign constraint checked on loading.
    required : bool
        Whether every vehicle of the kind must define it.
    """

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
    # --- rudder: side force and yaw moment per rudder angle (rudder angle in the [actuators] table)
    "K_SF_rudder": ParamSpec("kg/m/rad", "side force per rudder angle: SF = (K_beta beta + K_SF_rudder delta_r) V^2",
                             "any"),
    "K_MY_rudder": ParamSpec("kg/rad", "yaw moment per rudder angle: (K_MY beta + K_MY_rudder delta_r) V^2 "
                             "(> 0: a positive rudder angle turns the nose to starboard)", "any"),
    # --- elevator (§6.3); actuator limits are in the [actuators] table (ACTUATOR_SPECS)
    "delta": ParamSpec("kg/m/rad", "elevator moment-to-force coupling factor (§6.3)", "nonnegative"),
    "depth_rating": ParamSpec("m", "rated depth of the hull: missions deeper than this are refused", "positive"),
    "pump_efficiency": ParamSpec("1", "buoyancy pump efficiency (hydraulic work / electrical energy), 0 < e <= 1",
                                 "positive"),
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

#: Largest buoyancy-pump range accepted, as a fraction of the vehicle's mass (:func:`load_vehicle` refuses more):
#: no pump moves more water than the vehicle weighs (real ones move 0.5-2 %).
PUMP_FRACTION_MAX = 1.0

#: Range of ``density * volume / mass`` accepted: a glider's hull displaces within a few percent of its mass.
HULL_MASS_RATIO = (0.8, 1.25)

#: Densities (kg/m^3) a density profile may hold: sea water from fresh and warm to cold and deep.
DENSITY_RANGE = (990.0, 1080.0)

#: Default sea-water density (kg/m^3) where a vehicle file gives none: the constant gliderflight's steady-state
#: calibration uses and the value the field quotes for the upper ocean.
DEFAULT_DENSITY = 1025.0

#: The hull and water keys every law accepts in ``[hydrodynamics]`` (net buoyancy of a compressible hull).
_HULL: dict[str, ParamSpec] = {
    "density": ParamSpec("kg/m^3", f"sea-water density, constant (default {DEFAULT_DENSITY:g})", "positive"),
    "mass": ParamSpec("kg", "vehicle mass in air (hull, ballast, batteries, oil): the weight the buoyancy balances",
                      "positive"),
    "volume": ParamSpec("m^3", "hull volume at the surface at the reference temperature, pumped volume 0",
                        "positive"),
    "compressibility": ParamSpec("1/Pa", "hull compressibility epsilon: volume (1 - epsilon p) at gauge pressure p",
                                 "nonnegative"),
    "thermal_expansion": ParamSpec("1/K", "hull thermal expansion: volume (1 + alpha_T (T - T_ref))", "any"),
    "reference_temperature": ParamSpec("degC", "temperature at which the hull volume is 'volume'", "any"),
}

#: Lift and drag laws a vehicle file may choose with ``[hydrodynamics] law = "..."`` and each law's keys (besides
#: the hull keys): ``"thesis"`` uses ``K_L0, K_L, K_D0, K_D`` of ``[parameters]`` ((2.9), (2.11)); ``"seaglider"`` is
#: the Seaglider basestation model (Eriksen et al. 2001), angle of attack in degrees; ``"gliderflight"`` is the
#: steady-state model of Merckelbach et al. (2019), keys named as the ``gliderflight`` package names them.
_LAWS: dict[str, dict[str, ParamSpec]] = {
    "thesis": {},
    "seaglider": {
        "hd_a": ParamSpec("1/deg", "lift per degree of angle of attack: L = hd_a q l^2 alpha_deg", "positive", True),
        "hd_b": ParamSpec("Pa^(1/4)", "parasitic drag: D = (hd_b q^(-1/4) + hd_c alpha_deg^2) q l^2", "nonnegative",
                          True),
        "hd_c": ParamSpec("1/deg^2", "induced drag per squared degree of angle of attack", "nonnegative", True),
        "length": ParamSpec("m", "hull length l (reference area l^2)", "positive", True),
    },
    "gliderflight": {
        "Cd0": ParamSpec("1", "parasitic drag coefficient: D = q S (Cd0 + Cd1 alpha^2)", "nonnegative", True),
        "Cd1": ParamSpec("1/rad^2", "induced drag coefficient (default aw^2 / (pi eOsborne AR) + Cd1_hull)",
                         "nonnegative"),
        "ah": ParamSpec("1/rad", "hull lift slope: L = q S (ah + aw) alpha", "nonnegative"),
        "aw": ParamSpec("1/rad", "wing lift slope (default 2 pi AR / (2 + sqrt(AR^2 (1 + tan^2 Omega) + 4)))",
                        "nonnegative"),
        "S": ParamSpec("m^2", "wing reference area", "positive"),
        "AR": ParamSpec("1", "wing aspect ratio", "positive"),
        "eOsborne": ParamSpec("1", "Oswald (Osborne) efficiency of the wing", "positive"),
        "Omega": ParamSpec("rad", "wing sweep angle", "any"),
        "Cd1_hull": ParamSpec("1/rad^2", "induced drag coefficient of the hull", "nonnegative"),
    },
}

#: Defaults of the ``gliderflight`` law for keys a file leaves out: gliderflight's own (``ModelParameters``).
GLIDERFLIGHT_DEFAULTS: Mapping[str, float] = MappingProxyType(
    {"AR": 7.0, "Omega": 43.0 * math.pi / 180.0, "S": 0.1, "ah": 3.8, "eOsborne": 0.8, "Cd1_hull": 9.7})

#: Keys of ``[parameters]`` that the lift and drag law replaces: only the ``"thesis"`` law reads them.
THESIS_LIFT_DRAG_KEYS = ("K_L0", "K_L", "K_D0", "K_D")

#: Specification of the ``[hydrodynamics]`` keys per law: the law's keys plus the hull keys.
HYDRO_SPECS: Mapping[str, Mapping[str, ParamSpec]] = MappingProxyType(
    {law: MappingProxyType({**keys, **_HULL}) for law, keys in _LAWS.items()})


@dataclass(frozen=True)
class ActuatorSpec:
    """What an entry of the ``[actuators]`` table may describe.

    Attributes
    ----------
    unit : str
        Unit of ``min``, ``max`` and ``fixed``; ``rate`` is in ``unit/s``.
    description : str
        The actuated quantity, with the thesis symbol.
    """

    unit: str
    description: str


#: Actuators an underwater glider file may list in ``[actuators]`` (setting unit; rates are in unit/s).
ACTUATOR_SPECS: Mapping[str, ActuatorSpec] = MappingProxyType({
    "m0": ActuatorSpec("kg", "net buoyancy m0 set by the buoyancy pump (rate = pump rate u4 of (2.8))"),
    "r_P1": ActuatorSpec("m", "moving-mass position along body-1 (along the hull)"),
    "r_P2": ActuatorSpec("m", "moving-mass position along body-2 (lateral, roll)"),
    "r_P3": ActuatorSpec("m", "moving-mass position along body-3 (vertical offset)"),
    "elevator": ActuatorSpec("rad", "elevator: control angle of attack u2 of §6.3"),
    "roll": ActuatorSpec("rad", "battery roll by rotation about body-1: the moving mass sits at r_P2 = rho sin(phi_b), "
                         "r_P3 = rho cos(phi_b), rho = the r_P3 setting"),
    "rudder": ActuatorSpec("rad", "rudder angle delta_r (> 0 turns the nose to starboard; coefficients K_SF_rudder, "
                           "K_MY_rudder)"),
})

#: Keys that earlier vehicle files used for actuator limits, and where they went.
_MOVED_KEYS = {
    "u2_max": "elevator = { min = -u2_max, max = u2_max, unit = \"rad\", source = \"...\" }",
    "u4_max": "m0 = { ..., rate = u4_max, unit = \"kg\", source = \"...\" }",
    "m0_max": "m0 = { min = -m0_max, max = m0_max, unit = \"kg\", source = \"...\" }",
}

_ACTUATOR_FIELDS = {"min", "max", "rate", "fixed", "unit", "source", "note"}


@dataclass(frozen=True)
class Actuator:
    """Range and rate of one actuator (an entry of the vehicle file's ``[actuators]`` table).

    Parameters
    ----------
    name : str
        A key of :data:`ACTUATOR_SPECS` (``"m0"``, ``"r_P1"``, ..., ``"elevator"``, ``"rudder"``).
    min, max : float
        Range of the setting (unit of the spec: kg, m or rad); ``-inf``/``inf`` when unbounded. A fixed actuator
        has ``min = max = fixed`` unless a range is also given (the range the part could be set to on the bench).
    rate : float
        Largest rate of change (unit/s), ``inf`` when unlimited; 0 for a fixed actuator.
    fixed : float or None
        The setting of a part that is not actuated in flight, else ``None``.
    unit : str
        Unit of the setting.
    source : str
        Where the numbers come from.
    note : str
        Free text.

    Raises
    ------
    VehicleFileError
        Unknown name, wrong unit, non-finite or non-real numbers, ``min >= max``, a negative or zero rate, a fixed
        value outside its range, or a missing source.
    """

    name: str
    min: float = -math.inf
    max: float = math.inf
    rate: float = math.inf
    fixed: float | None = None
    unit: str = ""
    source: str = ""
    note: str = ""

    def __post_init__(self) -> None:
        where = f"actuator '{self.name}'"
        if self.name not in ACTUATOR_SPECS:
            raise VehicleFileError(f"unknown actuator {self.name!r}; known: {', '.join(ACTUATOR_SPECS)}")
        spec = ACTUATOR_SPECS[self.name]
        unit = self.unit or spec.unit
        if _norm_unit(unit) != _norm_unit(spec.unit):
            raise VehicleFileError(f"{where} has unit '{unit}', glidectl expects '{spec.unit}' (rate in "
                                   f"{spec.unit}/s): convert the values")
        object.__setattr__(self, "unit", spec.unit)
        vals = {}
        for key in ("min", "max", "rate", "fixed"):
            v = getattr(self, key)
            if v is None:
                vals[key] = None
                continue
            if not _is_real(v):
                raise VehicleFileError(f"{where}: '{key}' must be a real number, got {type(v).__name__} {v!r}")
            v = float(v)
            if math.isnan(v) or (key == "fixed" and not math.isfinite(v)):
                raise VehicleFileError(f"{where}: '{key}' must be a finite number, got {v!r}")
            if math.isfinite(v) and abs(v) > VALUE_MAX:
                raise VehicleFileError(f"{where}: '{key}' = {v:g} is beyond the plausibility limit {VALUE_MAX:g}")
            vals[key] = v
        lo, hi, rate, fixed = vals["min"], vals["max"], vals["rate"], vals["fixed"]
        if lo is None or hi is None or rate is None:
            raise VehicleFileError(f"{where}: 'min', 'max' and 'rate' must be numbers (omit a key for no limit)")
        if fixed is not None:
            if lo == -math.inf and hi == math.inf:
                lo = hi = fixed
            if rate != math.inf and rate != 0.0:
                raise VehicleFileError(f"{where}: a fixed actuator (fixed = {fixed:g}) cannot have a rate "
                                       f"({rate:g} {spec.unit}/s); drop 'rate' or 'fixed'")
            rate = 0.0
            if not lo <= fixed <= hi:
                raise VehicleFileError(f"{where}: fixed value {fixed:g} {spec.unit} is outside its range "
                                       f"[{lo:g}, {hi:g}] {spec.unit}")
        else:
            if not lo < hi:
                raise VehicleFileError(f"{where}: min = {lo:g} must be < max = {hi:g} {spec.unit}")
            if not rate > 0:
                raise VehicleFileError(f"{where}: rate must be > 0 {spec.unit}/s (omit it for no rate limit), "
                                       f"got {rate:g}")
        for key, v in (("source", self.source), ("note", self.note)):
            if not isinstance(v, str):
                raise VehicleFileError(f"{where}: '{key}' must be a string, got {v!r}")
        object.__setattr__(self, "min", lo)
        object.__setattr__(self, "max", hi)
        object.__setattr__(self, "rate", rate)
        object.__setattr__(self, "fixed", fixed)

    @property
    def actuated(self) -> bool:
        """True when the setting can be changed in flight (not ``fixed``)."""
        return self.fixed is None

    @property
    def bounds(self) -> tuple[float, float]:
        """``(min, max)`` of the setting in flight: ``(fixed, fixed)`` for a fixed actuator."""
        return (self.fixed, self.fixed) if self.fixed is not None else (self.min, self.max)

    def contains(self, value: Any, rtol: float = 1e-9) -> Any:
        """Whether ``value`` (scalar or array) lies in :attr:`bounds`, with a relative slack ``rtol``.

        Parameters
        ----------
        value : float or array_like
            Settings in the actuator's unit.
        rtol : float, optional
            Relative slack on the bounds (scaled by ``max(1, |bound|)``).

        Returns
        -------
        bool or ndarray of bool
        """
        lo, hi = self.bounds
        v = np.asarray(value, dtype=float)
        slack_lo = rtol * max(1.0, abs(lo)) if math.isfinite(lo) else 0.0
        slack_hi = rtol * max(1.0, abs(hi)) if math.isfinite(hi) else 0.0
        out = (v >= lo - slack_lo) & (v <= hi + slack_hi)
        return bool(out) if out.ndim == 0 else out

    def clip(self, value: Any) -> Any:
        """``value`` clipped to :attr:`bounds` (same shape)."""
        lo, hi = self.bounds
        return np.clip(value, lo, hi)

    def describe(self) -> str:
        """One-line summary such as ``[-0.25, 0.25] kg, 0.01 kg/s``."""
        if self.fixed is not None:
            return f"fixed {self.fixed:.6g} {self.unit}"
        rate = "no rate limit" if self.rate == math.inf else f"{self.rate:.6g} {self.unit}/s"
        return f"[{self.min:.6g}, {self.max:.6g}] {self.unit}, {rate}"

    def as_plain(self) -> dict[str, Any]:
        """Plain dict (for hashing, pickling and JSON)."""
        return {"name": self.name, "min": self.min, "max": self.max, "rate": self.rate, "fixed": self.fixed,
                "unit": self.unit, "source": self.source, "note": self.note}


def _norm_unit(u: str) -> str:
    return u.replace(" ", "").replace(".", "*").replace("·", "*")


@dataclass(frozen=True)
class Vehicle:
    """A validated, immutable vehicle description.

    Parameters are reached as attributes (``veh.m1``, ``veh.K_M``) or through :attr:`params`. ``provenance`` is
    a SHA-256 of the canonical parameter set (file values plus overrides), carried by every result computed from
    this vehicle. Make one with :func:`load_vehicle` (or :meth:`with_overrides`); constructing it directly applies
    the same validation as a vehicle file.

    Parameters
    ----------
    name, kind, title, path, notes : str
        As the attributes below.
    params : Mapping[str, float]
        Parameter values (SI units, angles in rad).
    sources : Mapping[str, str]
        Source of each value.
    overrides : Mapping[str, float], optional
        Values that replaced the file's.
    actuators : Mapping[str, Actuator], optional
        The ``[actuators]`` table (range and rate of the pump, moving mass, elevator, rudder).
    law : str, optional
        The lift and drag law of the ``[hydrodynamics]`` table: ``"thesis"`` (default), ``"seaglider"`` or
        ``"gliderflight"`` (:data:`HYDRO_SPECS`); its coefficients and the hull keys are entries of ``params``.
    density_profile : (depths, densities), optional
        Sea-water density against depth (m, kg/m^3), the ``[hydrodynamics.density_profile]`` table: depths
        strictly increasing from at least 0, densities of sea water (:data:`DENSITY_RANGE`). Empty: constant.
    uncertainty : Mapping[str, Uncertainty or Mapping], optional
        The ``[uncertainty]`` table: key -> :class:`~glidectl.Uncertainty`, or an inline table in the file's form
        (:mod:`glidectl.uncertainty`), resolved against the parameter values. Empty: none.
    correlation : Mapping or sequence, optional
        Correlations between normal entries, ``{"K_L,K_D": 0.6}`` or ``(( ("K_D", "K_L"), 0.6), ...)``.

    Raises
    ------
    ArgumentTypeError
        If a text field is not a ``str`` or ``params``, ``sources`` or ``overrides`` is not a mapping.
    VehicleFileError
        If ``kind`` is unknown, a parameter is unknown for the kind, not a finite real number, outside its sign
        constraint or plausibility limits (:data:`VALUE_MAX`, :data:`POSITIVE_MIN`), a required parameter is
        missing, the mass model is inconsistent, the law is unknown or a key belongs to another law, or the
        uncertainty table is invalid (unknown or actuated key, bad entry, bounds that exclude the nominal value,
        correlations that are not positive semidefinite).

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
    actuators : Mapping[str, Actuator]
        Range and rate of each actuator the file lists (``veh.actuators["m0"].max``); a fixed part's setting is
        also its nominal parameter (``veh.r_P3``).
    law : str
        The lift and drag law (:func:`glidectl.hydro.lift_drag`).
    density_profile : tuple
        ``(depths, densities)`` as tuples of floats, or ``()`` (:meth:`water_density`).
    uncertainty : Mapping[str, Uncertainty]
        How well each listed coefficient is known (absolute bounds and standard deviations), in the order of
        ``params``; empty without an ``[uncertainty]`` table (:meth:`sample`, :meth:`vertices`).
    correlation : tuple
        ``((key1, key2), rho)`` pairs between normal entries of ``uncertainty``, ``key1 < key2``, sorted.
    """

    name: str
    kind: str
    title: str
    params: Mapping[str, float]
    sources: Mapping[str, str]
    path: str
    overrides: Mapping[str, float] = field(default_factory=lambda: MappingProxyType({}))
    notes: str = ""
    actuators: Mapping[str, Actuator] = field(default_factory=lambda: MappingProxyType({}))
    law: str = "thesis"
    density_profile: tuple[Any, ...] = ()
    uncertainty: Mapping[str, Uncertainty] = field(default_factory=lambda: MappingProxyType({}))
    correlation: tuple[tuple[tuple[str, str], float], ...] = ()

    def __post_init__(self) -> None:
        for key in ("name", "kind", "title", "path", "notes", "law"):
            value = object.__getattribute__(self, key)
            if not isinstance(value, str):
                raise ArgumentTypeError(f"Vehicle {key} must be a str, got {type(value).__name__} {value!r}")
        for key in ("params", "sources", "overrides", "actuators", "uncertainty"):
            value = object.__getattribute__(self, key)
            if not isinstance(value, Mapping):
                raise ArgumentTypeError(f"Vehicle {key} must be a mapping, got {type(value).__name__}")
        if self.kind not in PARAMETER_SPECS:
            raise VehicleFileError(f"{self.path or self.name}: unknown vehicle kind '{self.kind}'; expected one of "
                                   f"{sorted(PARAMETER_SPECS)}")
        where = self.path or f"vehicle '{self.name}'"
        spec = _key_specs(self.kind, self.law, where)
        values: dict[str, float] = {}
        for key, value in self.params.items():
            if not isinstance(key, str) or key not in spec:
                raise VehicleFileError(f"{where}: {_unknown_key(key, self.kind, self.law)}")
            values[key] = _check_value(key, value, spec[key], where)
        srcs = dict(self.sources)
        if self.law == "gliderflight":  # gliderflight's own defaults for the wing keys a file leaves out
            for key, value in GLIDERFLIGHT_DEFAULTS.items():
                if key not in values:
                    values[key], srcs[key] = value, "gliderflight default (ModelParameters)"
        acts = _check_actuators(self.kind, self.actuators, values, where)
        for name, act in acts.items():  # a fixed part's setting is also the nominal parameter
            if act.fixed is not None and name in spec and name not in values:
                values[name] = act.fixed
                srcs[name] = f"[actuators] {name} (fixed): {act.source}"
        object.__setattr__(self, "sources", srcs)
        _check_consistency(self.kind, values, where, self.law)
        _check_actuator_scale(acts, values, where)
        object.__setattr__(self, "density_profile", _check_profile(self.density_profile, self.kind, where))
        table, corr = _check_uncertainty(self.uncertainty, self.correlation, values, self.kind, self.law, acts, where,
                                         "not recorded")
        object.__setattr__(self, "uncertainty", MappingProxyType(table))
        object.__setattr__(self, "correlation", corr)
        object.__setattr__(self, "actuators", MappingProxyType(acts))
        object.__setattr__(self, "params", MappingProxyType(values))
        object.__setattr__(self, "sources", MappingProxyType({str(k): str(v) for k, v in self.sources.items()}))
        object.__setattr__(self, "overrides", MappingProxyType(dict(self.overrides)))

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        # mappingproxy fields do not pickle; rebuild from plain dicts (used by pickle, copy and multiprocessing)
        return (_vehicle_from_plain, (self.name, self.kind, self.title, dict(self.params), dict(self.sources),
                                      self.path, dict(self.overrides), self.notes,
                                      {k: a.as_plain() for k, a in self.actuators.items()}, self.law,
                                      self.density_profile, {k: u.as_plain() for k, u in self.uncertainty.items()},
                                      self.correlation))

    def __getattr__(self, key: str) -> float:
        params = object.__getattribute__(self, "params")
        if key in params:
            return params[key]
        kind = object.__getattribute__(self, "kind")
        law = object.__getattribute__(self, "law")
        if kind == "underwater_glider" and law != "thesis" and key in THESIS_LIFT_DRAG_KEYS:
            raise ModelError(
                f"vehicle '{object.__getattribute__(self, 'name')}' uses the '{law}' lift and drag law "
                f"([hydrodynamics] law = \"{law}\"), which has no '{key}'; this computation needs the thesis law's "
                f"quadratic drag and linear lift ({', '.join(THESIS_LIFT_DRAG_KEYS)})")
        spec = {**PARAMETER_SPECS.get(kind, {}), **HYDRO_SPECS.get(law, {})}
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
        spec = _key_specs(self.kind, self.law, self.name)
        return MappingProxyType({k: spec[k].unit for k in self.params})

    @property
    def density(self) -> float:
        """Sea-water density (kg/m^3) of the models without depth: ``[hydrodynamics] density``, else the density
        profile's value at the surface, else :data:`DEFAULT_DENSITY`."""
        if "density" in self.params or not self.density_profile:
            return float(self.params.get("density", DEFAULT_DENSITY))
        return float(np.interp(0.0, *self.density_profile))

    def water_density(self, depth: Any) -> Any:
        """Sea-water density (kg/m^3) at ``depth`` (m): the density profile, linear between its points and constant
        beyond its ends, or the constant :attr:`density`.

        Parameters
        ----------
        depth : array_like
            Depth (m, positive down).

        Returns
        -------
        ndarray
            Density shaped like ``depth``.

        Raises
        ------
        ArgumentTypeError
            If ``depth`` is not an array of real numbers.
        """
        try:
            d = np.asarray(depth, dtype=float)
        except (TypeError, ValueError):
            raise ArgumentTypeError(f"depth must be real numbers (m), got {type(depth).__name__}") from None
        if not self.density_profile:
            return np.full(d.shape, self.density)
        return np.interp(d, *self.density_profile)

    @property
    def provenance(self) -> str:
        """SHA-256 (first 16 hex digits) of name, kind and the canonical parameter values (with the actuator
        limits, the law, the density profile and the uncertainty table where the vehicle has them)."""
        doc: dict[str, Any] = {"name": self.name, "kind": self.kind, "params": dict(sorted(self.params.items()))}
        if self.actuators:  # vehicles without an [actuators] table keep their earlier provenance
            doc["actuators"] = {k: [str(a.min), str(a.max), str(a.rate), str(a.fixed)]
                                for k, a in sorted(self.actuators.items())}
        if self.law != "thesis":  # vehicles of the thesis law keep their earlier provenance
            doc["law"] = self.law
        if self.density_profile:
            doc["density_profile"] = [list(map(repr, c)) for c in self.density_profile]
        if self.uncertainty:  # vehicles without an [uncertainty] table keep their earlier provenance
            doc["uncertainty"] = {k: [u.kind, repr(u.low), repr(u.high), repr(u.std)]
                                  for k, u in sorted(self.uncertainty.items())}
            if self.correlation:
                doc["correlation"] = [[a, b, repr(r)] for (a, b), r in self.correlation]
        blob = json.dumps(doc, sort_keys=True)
        return hashlib.sha256(blob.encode()).hexdigest()[:16]

    def has(self, *keys: str) -> bool:
        """True when every key in ``keys`` is defined.

        Parameters
        ----------
        *keys : str
            Parameter names.

        Returns
        -------
        bool

        Raises
        ------
        ArgumentTypeError
            If a key is not a string.
        """
        for k in keys:
            if not isinstance(k, str):
                raise ArgumentTypeError(f"parameter names must be strings, got {type(k).__name__} {k!r}")
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
            ``m_i = m + m0 - mbar + m_fi`` (§2.2.2 with the chapter 8 convention of docs/conventions.md). Arrays
            (also complex, for complex-step derivatives) are used elementwise; default the file's ``m0``.

        Returns
        -------
        float or ndarray
            ``m_i`` (kg), shaped like ``m0``.

        Raises
        ------
        ArgumentTypeError
            If ``axis`` is not an integer or ``m0`` is not a number or an array of numbers.
        ArgumentError
            If ``axis`` is not 1, 2 or 3.
        ModelError
            If the vehicle is not an underwater glider (a CTOL aircraft has the single mass ``m``), or does not
            define the mass needed (``m2`` for 3D work, ``m0`` for the default).
        """
        if self.kind != "underwater_glider":
            raise ModelError(f"vehicle '{self.name}' is a {self.kind}: body-axis masses m_i belong to underwater "
                             "gliders; use its mass m")
        if not (type(axis) is int and 1 <= axis <= 3):  # (a plain int axis, the right-hand sides' calls, is valid)
            if isinstance(axis, bool | np.bool_) or not isinstance(axis, numbers.Integral):
                raise ArgumentTypeError(f"axis must be the integer 1, 2 or 3, got {type(axis).__name__} {axis!r}")
            if axis not in (1, 2, 3):
                raise ArgumentError(f"axis must be 1, 2 or 3 (body axes), got {axis!r}")
            axis = int(axis)
        if m0 is not None and type(m0) not in (float, np.float64) and \
                not (isinstance(m0, numbers.Real) and not isinstance(m0, bool)):
            if isinstance(m0, bool | np.bool_ | str | bytes) or np.asarray(m0).dtype.kind not in "iufc":
                raise ArgumentTypeError(f"m0 must be a number (kg) or an array of numbers, got "
                                        f"{type(m0).__name__} {m0!r}")
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
        """Return a new validated vehicle with some parameters replaced (same rules as the file).

        Parameters
        ----------
        **overrides : float
            Parameter values (SI units), e.g. ``K_M=-100.0``.

        Returns
        -------
        Vehicle
            A new vehicle; ``self`` is unchanged. It keeps the ``[uncertainty]`` table, except an entry whose bounds
            exclude its overridden value (dropped with its correlations: the table describes values about the
            nominal, and sweeps and designs may move a coefficient beyond them).

        Raises
        ------
        VehicleFileError
            An unknown parameter, a value that is not a finite real number or breaks a sign constraint or a
            plausibility limit, or an inconsistent mass model.
        """
        return _build_vehicle(self.name, self.kind, self.title, dict(self.params), dict(self.sources),
                              self.path, {**self.overrides, **overrides}, self.notes, overrides,
                              dict(self.actuators), self.law, self.density_profile, self.uncertainty,
                              self.correlation)

    def with_hydrodynamics(self, law: str | None = None, *, source: str = "with_hydrodynamics",
                           **coefficients: float) -> Vehicle:
        """Return a new vehicle with another lift and drag law or new law and hull coefficients.

        Switching law drops the old law's coefficients (for the thesis law, ``K_L0, K_L, K_D0, K_D`` of
        ``[parameters]``) and keeps the hull keys; the new law's required coefficients must then be given. The
        ``[uncertainty]`` entries of dropped keys, and of keys whose new value their bounds exclude, are dropped.

        Parameters
        ----------
        law : str, optional
            ``"thesis"``, ``"seaglider"`` or ``"gliderflight"`` (:data:`HYDRO_SPECS`); default the vehicle's.
        source : str, optional
            Source recorded for every value given here (a fit names its record).
        **coefficients : float
            Law and hull coefficients in the units of :data:`HYDRO_SPECS` (thesis law: ``K_L0`` ... of
            :data:`PARAMETER_SPECS`).

        Returns
        -------
        Vehicle

        Raises
        ------
        VehicleFileError
            An unknown law, a key the law does not know, a value outside its limits, or a required coefficient
            missing.
        """
        new_law = self.law if law is None else law
        if not isinstance(new_law, str) or new_law not in HYDRO_SPECS:
            raise VehicleFileError(f"vehicle '{self.name}': {_unknown_law(new_law)}")
        values, sources, overrides = dict(self.params), dict(self.sources), dict(self.overrides)
        if new_law != self.law:
            old = THESIS_LIFT_DRAG_KEYS if self.law == "thesis" else tuple(_LAWS[self.law])
            for key in old:
                values.pop(key, None)
                sources.pop(key, None)
                overrides.pop(key, None)
        spec = _key_specs(self.kind, new_law, self.name)
        for key, value in coefficients.items():
            if key not in spec:
                raise VehicleFileError(f"vehicle '{self.name}': {_unknown_key(key, self.kind, new_law)}")
            values[key] = _check_value(key, value, spec[key], f"vehicle '{self.name}'")
            sources[key] = source
        table, corr = keep_contained(self.uncertainty, self.correlation, values)
        return Vehicle(name=self.name, kind=self.kind, title=self.title, params=values, sources=sources,
                       path=self.path, overrides=overrides, notes=self.notes, actuators=dict(self.actuators),
                       law=new_law, density_profile=self.density_profile, uncertainty=table, correlation=corr)

    def with_actuators(self, **actuators: Mapping[str, Any] | Actuator | None) -> Vehicle:
        """Return a new vehicle with some actuator entries replaced, added or (with ``None``) removed.

        Parameters
        ----------
        **actuators : Actuator, mapping or None
            ``name=Actuator(...)``, or a mapping of the fields of an ``[actuators]`` entry such as
            ``m0={"min": -0.25, "max": 0.25, "rate": 0.01, "source": "pump datasheet"}``; ``None`` removes it.

        Returns
        -------
        Vehicle

        Raises
        ------
        VehicleFileError
            An invalid entry (as in a vehicle file), or an actuator on a key of the ``[uncertainty]`` table.
        """
        acts: dict[str, Actuator] = dict(self.actuators)
        for name, entry in actuators.items():
            if entry is None:
                acts.pop(name, None)
            elif isinstance(entry, Actuator):
                acts[name] = entry
            elif isinstance(entry, Mapping):
                acts[name] = _actuator_from_entry(name, dict(entry), f"vehicle '{self.name}'", require_source=False)
            else:
                raise VehicleFileError(f"actuator '{name}' must be an Actuator, a mapping or None, got "
                                       f"{type(entry).__name__}")
        return Vehicle(name=self.name, kind=self.kind, title=self.title, params=self.params, sources=self.sources,
                       path=self.path, overrides=self.overrides, notes=self.notes, actuators=acts, law=self.law,
                       density_profile=self.density_profile, uncertainty=self.uncertainty,
                       correlation=self.correlation)

    def with_uncertainty(self, uncertainty: Mapping[str, Any], correlation: Any = None) -> Vehicle:
        """Return a new vehicle whose ``[uncertainty]`` table is ``uncertainty`` (replacing the whole table).

        Parameters
        ----------
        uncertainty : Mapping
            Key -> an entry in the vehicle file's form, e.g. ``{"K_M": {"rel": 0.3}, "K_L": {"std": 2.0}}``
            (:mod:`glidectl.uncertainty`; ``source`` defaults to ``"Vehicle.with_uncertainty"``), or an
            :class:`~glidectl.Uncertainty`. A ``"correlation"`` key may hold the correlations as in the file.
            ``{}`` removes the table.
        correlation : Mapping or sequence, optional
            ``{"K_L,K_D": 0.6}``, ``{("K_L", "K_D"): 0.6}`` or ``((("K_D", "K_L"), 0.6), ...)``.

        Returns
        -------
        Vehicle
            The same parameters with the new table; relative entries are resolved against its values.

        Raises
        ------
        ArgumentTypeError
            If ``uncertainty`` is not a mapping.
        VehicleFileError
            An invalid entry or correlation, with the same checks and messages as a vehicle file.
        """
        if not isinstance(uncertainty, Mapping):
            raise ArgumentTypeError(f"uncertainty must be a mapping of key -> entry, got {type(uncertainty).__name__}")
        entries = dict(uncertainty)
        if "correlation" in entries:
            if correlation is not None:
                raise VehicleFileError(f"vehicle '{self.name}': correlations are given twice (the 'correlation' "
                                       "entry and the correlation argument)")
            correlation = entries.pop("correlation")
        table, corr = _check_uncertainty(entries, correlation, self.params, self.kind, self.law, self.actuators,
                                         f"vehicle '{self.name}'", "Vehicle.with_uncertainty")
        return Vehicle(name=self.name, kind=self.kind, title=self.title, params=self.params, sources=self.sources,
                       path=self.path, overrides=self.overrides, notes=self.notes, actuators=dict(self.actuators),
                       law=self.law, density_profile=self.density_profile, uncertainty=table, correlation=corr)

    def _uncertain(self) -> None:
        if not self.uncertainty:
            raise ArgumentError(f"vehicle '{self.name}' has no [uncertainty] entries to sample: add an [uncertainty] "
                                f"table to its file ({self.path}) or use Vehicle.with_uncertainty")

    def sample_overrides(self, n: int, seed: int = 0) -> tuple[np.ndarray, tuple[str, ...]]:
        """``n`` random draws of the uncertain coefficients, without building vehicles.

        Intervals are uniform, normal entries Gaussian about the nominal value (correlated through the Cholesky
        factor of their correlation matrix; truncated ones within their bounds). Sample ``i`` has its own random
        stream, child ``i`` of ``numpy.random.SeedSequence(seed).spawn(n)``: the first ``m`` rows are the same
        for every ``n >= m`` (:mod:`glidectl.uncertainty`).

        Parameters
        ----------
        n : int
            Number of samples, 1 to 10^7.
        seed : int, optional
            Seed, >= 0.

        Returns
        -------
        (ndarray, tuple of str)
            The ``(n, k)`` values (parameters' units) and the ``k`` keys of the columns (the table's order).

        Raises
        ------
        ArgumentTypeError
            If ``n`` or ``seed`` is not an integer.
        ArgumentError
            If the vehicle has no ``[uncertainty]`` entry, ``n`` or ``seed`` is out of range, or a correlated
            truncated normal cannot be drawn within its bounds.
        """
        n = integer("n", n, lo=1, hi=10**7)
        seed = integer("seed", seed, lo=0)
        self._uncertain()
        keys, values = draw_values(self.uncertainty, self.correlation, self.params, n, seed)
        return values, keys

    def sample(self, n: int, seed: int = 0, on_invalid: Literal["record", "raise"] = "record") -> VehicleSample:
        """``n`` vehicles drawn from the ``[uncertainty]`` table (:meth:`sample_overrides`), each
        ``self.with_overrides(...)`` of its sampled coefficients (its ``overrides`` record them).

        A draw that makes the vehicle invalid (a negative buoyancy mass, a negative lift slope in the tail of a
        normal entry...) is kept as ``None`` in :attr:`VehicleSample.vehicles` with the reason in
        :attr:`VehicleSample.errors`; iterating the result gives the valid vehicles.

        Parameters
        ----------
        n : int
            Number of samples, 1 to 10^7.
        seed : int, optional
            Seed, >= 0 (sample ``i`` is the same for every ``n > i``).
        on_invalid : {"record", "raise"}, optional
            ``"raise"``: raise at the first invalid sample instead.

        Returns
        -------
        VehicleSample

        Raises
        ------
        ArgumentTypeError
            If ``n`` or ``seed`` is not an integer.
        ArgumentError
            As :meth:`sample_overrides`, or an unknown ``on_invalid``.
        VehicleFileError
            With ``on_invalid="raise"``, the first invalid sample (its index and the reason).
        """
        if on_invalid not in ("record", "raise"):
            raise ArgumentError(f"on_invalid must be 'record' or 'raise', got {on_invalid!r}")
        values, keys = self.sample_overrides(n, seed)
        return self._sample_of(keys, values, "random", seed, on_invalid == "raise")

    def vertices(self, max_vertices: int = 1024, seed: int = 0) -> VehicleSample:
        """Vehicles at the corners of the box of the uncertain coefficients.

        The box spans each interval, and each normal entry's truncation bounds where finite, else the nominal
        value -+ 3 standard deviations (:data:`~glidectl.uncertainty.VERTEX_STDS`); correlations are ignored. With
        ``k`` entries, all ``2^k`` corners when ``2^k <= max_vertices`` (binary order, the first key varying
        slowest); otherwise ``max_vertices`` points: the nominal vehicle, the ``2k`` axis extremes (one coefficient
        at its low, then its high bound, the others nominal), and distinct corners drawn with ``seed``
        (:func:`glidectl.uncertainty.vertex_values`). Invalid corners are recorded as in :meth:`sample`.

        Parameters
        ----------
        max_vertices : int, optional
            Most points, 1 to 10^6.
        seed : int, optional
            Seed of the random corners, >= 0.

        Returns
        -------
        VehicleSample

        Raises
        ------
        ArgumentTypeError
            If ``max_vertices`` or ``seed`` is not an integer.
        ArgumentError
            If the vehicle has no ``[uncertainty]`` entry, or not all corners fit and ``max_vertices < 2k + 1``.
        """
        max_vertices = integer("max_vertices", max_vertices, lo=1, hi=10**6)
        seed = integer("seed", seed, lo=0)
        self._uncertain()
        keys, values = vertex_values(self.uncertainty, self.params, max_vertices, seed)
        return self._sample_of(keys, values, "vertices", seed, False)

    def _sample_of(self, keys: tuple[str, ...], values: np.ndarray, method: str, seed: int,
                   raise_invalid: bool) -> VehicleSample:
        vehicles: list[Vehicle | None] = []
        errors: list[str | None] = []
        for i, row in enumerate(values):
            try:
                vehicles.append(self.with_overrides(**dict(zip(keys, row.tolist(), strict=True))))
                errors.append(None)
            except VehicleFileError as exc:
                if raise_invalid:
                    raise VehicleFileError(f"sample {i} of vehicle '{self.name}' is invalid: {exc}") from None
                vehicles.append(None)
                errors.append(str(exc))
        values.setflags(write=False)
        return VehicleSample(vehicle=self, keys=keys, values=values, vehicles=tuple(vehicles), errors=tuple(errors),
                             method=method, seed=seed)

    def to_toml(self) -> str:
        """The vehicle as the text of a vehicle file that :func:`load_vehicle` reads back to the same values.

        Returns
        -------
        str
            TOML with ``[vehicle]``, ``[parameters]``, ``[hydrodynamics]`` (for a law other than the thesis's or
            hull keys), ``[actuators]`` and ``[uncertainty]`` (in absolute form: ``min``/``max`` or ``std``); every
            value written exactly (``repr`` of the float), with its unit and source.
        """
        spec = _key_specs(self.kind, self.law, self.name)
        hydro = set(HYDRO_SPECS[self.law]) if self.kind == "underwater_glider" else set()

        def entry(key: str, value: float) -> str:
            return (f"{key} = {{ value = {_toml_float(value)}, unit = {_toml_str(spec[key].unit)}, "
                    f"source = {_toml_str(self.sources.get(key) or 'not recorded')} }}")

        lines = ["[vehicle]", f"name = {_toml_str(self.name)}", f"kind = {_toml_str(self.kind)}",
                 f"title = {_toml_str(self.title)}"]
        if self.source:
            lines.append(f"source = {_toml_str(self.source)}")
        if self.notes:
            lines.append(f"notes = {_toml_str(self.notes)}")
        fixed = {k for k, a in self.actuators.items() if a.fixed is not None}
        lines += ["", "[parameters]"]
        lines += [entry(k, v) for k, v in self.params.items() if k not in hydro and k not in fixed]
        if self.law != "thesis" or hydro & set(self.params) or self.density_profile:
            lines += ["", "[hydrodynamics]", f"law = {_toml_str(self.law)}"]
            lines += [entry(k, v) for k, v in self.params.items() if k in hydro]
        if self.density_profile:
            lines += ["", "[hydrodynamics.density_profile]"]
            for key, unit, values in (("depth", "m", self.density_profile[0]),
                                      ("density", "kg/m^3", self.density_profile[1])):
                src = _toml_str(self.sources.get(f"density_profile.{key}") or "not recorded")
                lines.append(f"{key} = {{ values = [{', '.join(map(_toml_float, values))}], unit = \"{unit}\", "
                             f"source = {src} }}")
        if self.actuators:
            lines += ["", "[actuators]"]
            for name, a in self.actuators.items():
                fields = ([f"fixed = {_toml_float(a.fixed)}"] if a.fixed is not None else
                          [f"min = {_toml_float(a.min)}", f"max = {_toml_float(a.max)}"]
                          + ([f"rate = {_toml_float(a.rate)}"] if math.isfinite(a.rate) else []))
                fields += [f"unit = {_toml_str(a.unit or ACTUATOR_SPECS[name].unit)}",
                           f"source = {_toml_str(a.source or 'not recorded')}"]
                if a.note:
                    fields.append(f"note = {_toml_str(a.note)}")
                lines.append(f"{name} = {{ {', '.join(fields)} }}")
        if self.uncertainty:
            lines += ["", "[uncertainty]"]
            for key, u in self.uncertainty.items():
                fields = [f"{f} = {_toml_str(v) if f == 'source' else _toml_float(v)}" for f, v in u.as_entry().items()]
                lines.append(f"{key} = {{ {', '.join(fields)} }}")
            if self.correlation:
                lines += ["", "[uncertainty.correlation]"]
                lines += [f"{_toml_str(f'{a},{b}')} = {_toml_float(r)}" for (a, b), r in self.correlation]
        return "\n".join(lines) + "\n"

    def actuator_bounds(self, name: str, default: tuple[float, float] = (-math.inf, math.inf)) -> tuple[float, float]:
        """Flight range of actuator ``name``, or ``default`` when the file does not list it.

        Parameters
        ----------
        name : str
            Actuator key (``"m0"``, ``"r_P1"``, ...).
        default : (float, float), optional
            Range returned for an actuator the file does not list.

        Returns
        -------
        (float, float)

        Raises
        ------
        ArgumentError
            If ``name`` is not an actuator key.
        """
        if name not in ACTUATOR_SPECS:
            raise ArgumentError(f"unknown actuator {name!r}; known: {', '.join(ACTUATOR_SPECS)}")
        a = self.actuators.get(name)
        return a.bounds if a is not None else (float(default[0]), float(default[1]))

    @property
    def source(self) -> str:
        """The vehicle file's own ``[vehicle] source`` (where the vehicle as a whole comes from; "" when the file
        gives none); kept in :attr:`sources` under :data:`FILE_SOURCE_KEY`."""
        return str(self.sources.get(FILE_SOURCE_KEY, ""))

    def summary_rows(self) -> list[tuple[str, str, str, str]]:
        """(key, value, unit, source) rows for reports.

        Returns
        -------
        list of tuple of str
            One ``(key, value, unit, source)`` row per parameter.
        """
        spec = _key_specs(self.kind, self.law, self.name)
        rows = [(k, f"{v:.6g}", spec[k].unit, self.sources.get(k, "")) for k, v in self.params.items()]
        if self.law != "thesis":
            rows.insert(0, ("[hydrodynamics] law", self.law, "", "lift and drag law (glidectl.hydro.lift_drag)"))
        if self.density_profile:
            d, rho = self.density_profile
            rows.append(("[hydrodynamics] density_profile", f"{len(d)} points, {d[0]:g}-{d[-1]:g} m, "
                         f"{min(rho):.6g}-{max(rho):.6g} kg/m^3", "m, kg/m^3",
                         "; ".join(self.sources.get(f"density_profile.{k}", "") for k in ("depth", "density"))))
        for k, a in self.actuators.items():
            rows.append((f"[actuator] {k}", a.describe(), a.unit, a.source))
        if self.uncertainty:
            units = self.units
            rows += [(f"[uncertainty] {k}", u.describe(), units[k], u.source) for k, u in self.uncertainty.items()]
            rows += [(f"[uncertainty] correlation {a},{b}", f"{r:.6g}", "1", "") for (a, b), r in self.correlation]
        return rows


@dataclass(frozen=True, eq=False)
class VehicleSample:
    """Vehicles drawn from a vehicle's ``[uncertainty]`` table (:meth:`Vehicle.sample`, :meth:`Vehicle.vertices`).

    Row ``i`` of ``values`` gives the coefficients ``keys`` of sample ``i``; ``vehicles[i]`` is the nominal vehicle
    with them as overrides, or ``None`` when they make it invalid, the reason then being ``errors[i]``. ``len``,
    iteration and indexing go over the valid vehicles only, in sample order (``vehicles`` keeps every index).

    Attributes
    ----------
    vehicle : Vehicle
        The nominal vehicle sampled.
    keys : tuple of str
        The uncertain coefficients (columns of ``values``).
    values : ndarray
        ``(n, k)`` sampled values in the parameters' units (read-only).
    vehicles : tuple
        One :class:`Vehicle` per sample, ``None`` where invalid.
    errors : tuple
        ``None`` per valid sample, else why it is invalid (the vehicle file error's message).
    method : str
        ``"random"`` (:meth:`Vehicle.sample`) or ``"vertices"`` (:meth:`Vehicle.vertices`).
    seed : int
        The seed used.
    """

    vehicle: Vehicle = field(repr=False)
    keys: tuple[str, ...]
    values: np.ndarray = field(repr=False)
    vehicles: tuple[Vehicle | None, ...] = field(repr=False)
    errors: tuple[str | None, ...] = field(repr=False)
    method: str
    seed: int

    @property
    def valid(self) -> np.ndarray:
        """Boolean array, True where the sample is a valid vehicle."""
        return np.array([v is not None for v in self.vehicles], dtype=bool)

    @property
    def provenance(self) -> str:
        """The nominal vehicle's parameter hash."""
        return self.vehicle.provenance

    def _valid(self) -> list[Vehicle]:
        return [v for v in self.vehicles if v is not None]

    def __len__(self) -> int:
        return sum(v is not None for v in self.vehicles)

    def __iter__(self) -> Iterator[Vehicle]:
        return iter(self._valid())

    def __getitem__(self, index: int | slice) -> Any:
        return self._valid()[index]

    def stacked(self) -> StackedVehicle:
        """The valid samples as one :class:`StackedVehicle` (rows in sample order), for batched right-hand sides.

        Raises
        ------
        ArgumentError
            If no sample is valid.
        """
        return stack_vehicles(self._valid())

    def summary(self) -> str:
        """The number of samples, how many are valid, and the first reason a sample is invalid."""
        n = len(self.vehicles)
        head = (f"{n} {'random samples' if self.method == 'random' else 'vertices'} of {', '.join(self.keys)} "
                f"(vehicle '{self.vehicle.name}', seed {self.seed}): {len(self)} valid")
        bad = [(i, e) for i, e in enumerate(self.errors) if e is not None]
        return head if not bad else f"{head}; first invalid, sample {bad[0][0]}: {bad[0][1]}"


class StackedVehicle(Vehicle):
    """Several vehicles that differ only in parameter values, as one vehicle whose differing parameters are arrays
    (one entry per member, in order): :func:`stack_vehicles`.

    The models' right-hand sides broadcast over such parameters, so one call on states of shape ``(N, n)``
    evaluates each member on its own row, to the bit what the member gives alone. Each member was validated as a
    :class:`Vehicle`; the stack is not validated again, and what needs scalar parameters (trims, designs,
    :meth:`with_overrides`) is for the members, not the stack.

    Attributes
    ----------
    members : tuple of Vehicle
        The stacked vehicles.
    """

    members: tuple[Vehicle, ...]

    @property
    def size(self) -> int:
        """Number of members (the length of every array parameter)."""
        return len(self.members)

    @property
    def provenance(self) -> str:
        """SHA-256 (first 16 hex digits) of the members' provenances."""
        blob = json.dumps([v.provenance for v in self.members])
        return hashlib.sha256(blob.encode()).hexdigest()[:16]

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        return (stack_vehicles, (list(self.members),))


def stack_vehicles(vehicles: Any) -> StackedVehicle:
    """One :class:`StackedVehicle` of ``vehicles``: a parameter equal in every member stays a number, one that
    differs becomes an array of shape ``(N,)``.

    Parameters
    ----------
    vehicles : sequence of Vehicle
        Vehicles of the same kind, law, name, parameter keys, actuators and density profile (samples of one
        vehicle file, :meth:`VehicleSample.stacked`).

    Returns
    -------
    StackedVehicle

    Raises
    ------
    ArgumentTypeError
        If an element is not a Vehicle.
    ArgumentError
        If the sequence is empty or the vehicles differ in more than parameter values.
    """
    members = tuple(vehicles)
    if not members:
        raise ArgumentError("stack_vehicles needs at least one vehicle")
    for v in members:
        if not isinstance(v, Vehicle) or isinstance(v, StackedVehicle):
            raise ArgumentTypeError(f"stack_vehicles takes Vehicles, got {type(v).__name__}")
    first = members[0]
    for v in members[1:]:
        same = (v.kind == first.kind and v.law == first.law and v.name == first.name and
                set(v.params) == set(first.params) and dict(v.actuators) == dict(first.actuators) and
                v.density_profile == first.density_profile)
        if not same:
            raise ArgumentError(f"stack_vehicles: vehicle '{v.name}' differs from '{first.name}' in more than "
                                "parameter values (kind, law, keys, actuators or density profile)")
    params: dict[str, Any] = {}
    for key, value in first.params.items():
        column = np.array([v.params[key] for v in members], dtype=float)
        params[key] = value if np.all(column == value) else column
    out = object.__new__(StackedVehicle)
    for f in Vehicle.__dataclass_fields__:
        object.__setattr__(out, f, getattr(first, f))
    object.__setattr__(out, "params", MappingProxyType(params))
    object.__setattr__(out, "overrides", MappingProxyType({}))
    object.__setattr__(out, "members", members)
    return out


def _check_uncertainty(entries: Any, correlation: Any, values: Mapping[str, float], kind: str, law: str,
                       actuators: Mapping[str, Actuator], where: str,
                       default_source: str | None) -> tuple[dict[str, Uncertainty], Any]:
    """:func:`glidectl.uncertainty.check_uncertainty` for a vehicle of ``kind`` and ``law`` with ``actuators``."""
    if not entries and not correlation:
        return {}, ()
    spec = _key_specs(kind, law, where)

    def unknown(key: str) -> str:
        if key in ACTUATOR_SPECS:
            return f"'{key}' is an actuator: its range is in [actuators]; [uncertainty] takes coefficients"
        return _unknown_key(key, kind, law)

    return check_uncertainty(entries, correlation, values, {k: s.constraint for k, s in spec.items()},
                             {n: "fixed" if a.fixed is not None else "actuated" for n, a in actuators.items()},
                             where, unknown, default_source, VALUE_MAX)


def _toml_str(text: str) -> str:
    """``text`` as a TOML basic string: real code points (JSON's surrogate-pair escapes are not TOML), with the
    quote, the backslash and the control characters TOML forbids escaped."""
    body = json.dumps(str(text), ensure_ascii=False)
    return body.replace("\x7f", "\\u007f")


def _toml_float(value: float) -> str:
    """A float as TOML writes it exactly (``inf``, ``-inf``; ``repr`` otherwise)."""
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return repr(float(value))


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

    Examples
    --------
    >>> import glidectl as gc
    >>> gc.list_presets()
    ['dc8_ctol', 'elevator_ch6', 'rogue', 'slocum_ch8', 'slocum_shallow', 'sphere_ch5']
    """
    return sorted(p.name[:-5] for p in _presets_dir().iterdir() if p.name.endswith(".toml"))


def _is_real(value: Any) -> bool:
    """A Python or numpy real scalar (0-d real arrays included), never a bool."""
    if isinstance(value, bool | np.bool_):
        return False
    if isinstance(value, np.ndarray):
        return value.ndim == 0 and value.dtype.kind in "iuf"
    return isinstance(value, numbers.Real)


def _check_value(key: str, value: Any, spec: ParamSpec, where: str) -> float:
    if not _is_real(value):
        raise VehicleFileError(f"{where}: parameter '{key}' must be a real number, got "
                               f"{type(value).__name__} {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise VehicleFileError(f"{where}: parameter '{key}' must be finite, got {value!r}")
    if spec.constraint == "positive" and not v > 0:
        raise VehicleFileError(f"{where}: parameter '{key}' ({spec.description}) must be > 0, got {v:g}")
    if spec.constraint == "nonnegative" and not v >= 0:
        raise VehicleFileError(f"{where}: parameter '{key}' ({spec.description}) must be >= 0, got {v:g}")
    if abs(v) > VALUE_MAX:
        raise VehicleFileError(f"{where}: parameter '{key}' = {v:g} {spec.unit} is beyond the plausibility limit "
                               f"|value| <= {VALUE_MAX:g} (SI units); check the unit")
    if spec.constraint == "positive" and v < POSITIVE_MIN:
        raise VehicleFileError(f"{where}: parameter '{key}' = {v:g} {spec.unit} is below the plausibility limit "
                               f"{POSITIVE_MIN:g} for a positive parameter; check the unit")
    return v


def _unknown_law(law: Any) -> str:
    """The message for a law name that is not one of :data:`HYDRO_SPECS`, with a "did you mean"."""
    near = difflib.get_close_matches(str(law), list(HYDRO_SPECS), n=1)
    hint = f" (did you mean '{near[0]}'?)" if near else ""
    return f"unknown hydrodynamic law {law!r}{hint}; known: {', '.join(HYDRO_SPECS)}"


def _key_specs(kind: str, law: str, where: str) -> dict[str, ParamSpec]:
    """Every key a vehicle of ``kind`` with lift and drag ``law`` may define, with its specification."""
    if law not in HYDRO_SPECS:
        raise VehicleFileError(f"{where}: {_unknown_law(law)}")
    if kind != "underwater_glider":
        if law != "thesis":
            raise VehicleFileError(f"{where}: a [hydrodynamics] law is defined for underwater gliders only, not "
                                   f"{kind}")
        return dict(PARAMETER_SPECS.get(kind, {}))
    spec = dict(PARAMETER_SPECS[kind])
    if law != "thesis":
        for key in THESIS_LIFT_DRAG_KEYS:
            del spec[key]
    return {**spec, **HYDRO_SPECS[law]}


def _unknown_key(key: Any, kind: str, law: str) -> str:
    """The message for a key no table of this vehicle knows: another law's key, or a "did you mean"."""
    if kind not in PARAMETER_SPECS:
        return f"unknown vehicle kind '{kind}'; expected one of {sorted(PARAMETER_SPECS)}"
    owners = [other for other, keys in _LAWS.items() if key in keys]
    if kind == "underwater_glider" and key in THESIS_LIFT_DRAG_KEYS and law != "thesis":
        owners = ["thesis"]
    if owners:
        return (f"'{key}' belongs to the '{owners[0]}' hydrodynamic law, not to this vehicle's '{law}' law "
                f"([hydrodynamics] law = \"{law}\"): remove it or choose law = \"{owners[0]}\"")
    known = list(_key_specs(kind, law, ""))
    near = difflib.get_close_matches(str(key), known, n=1, cutoff=0.6)
    hint = f" (did you mean '{near[0]}'?)" if near else ""
    return f"unknown parameter {key!r}{hint} for a {kind} vehicle with the '{law}' law; known: {', '.join(known)}"


def _check_profile(profile: Any, kind: str, where: str) -> tuple[Any, ...]:
    """A density profile ``(depths, densities)`` as two tuples of floats, checked; ``()`` for none."""
    if profile is None or (isinstance(profile, tuple | list) and len(profile) == 0):
        return ()
    if kind != "underwater_glider":
        raise VehicleFileError(f"{where}: a density profile is defined for underwater gliders only, not {kind}")
    try:
        depths, dens = (np.asarray(c, dtype=float) for c in profile)
    except (TypeError, ValueError):
        raise VehicleFileError(f"{where}: density_profile must be (depths, densities), two lists of numbers, got "
                               f"{profile!r}") from None
    if depths.ndim != 1 or depths.shape != dens.shape or depths.size < 2:
        raise VehicleFileError(f"{where}: density_profile needs depth and density lists of the same length (at least "
                               f"2 points), got {depths.size} and {dens.size}")
    if not (np.all(np.isfinite(depths)) and np.all(np.isfinite(dens))):
        raise VehicleFileError(f"{where}: density_profile values must be finite")
    if depths[0] < 0 or np.any(np.diff(depths) <= 0):
        raise VehicleFileError(f"{where}: density_profile depths must increase strictly from 0 m or deeper, got "
                               f"{depths.tolist()}")
    lo, hi = DENSITY_RANGE
    if np.any(dens < lo) or np.any(dens > hi):
        hint = " (sigma-t? give rho = 1000 + sigma-t)" if np.all(np.abs(dens) < 100) else ""
        raise VehicleFileError(f"{where}: density_profile densities must be sea water, {lo:g}-{hi:g} kg/m^3, got "
                               f"{dens.min():g}-{dens.max():g}{hint}")
    return (tuple(depths.tolist()), tuple(dens.tolist()))


def _check_actuator_scale(acts: Mapping[str, Actuator], values: Mapping[str, float], where: str) -> None:
    """Refuse a buoyancy-pump range that no glider of this mass can have (a range typed in cm^3 or grams).

    A buoyancy engine moves a few percent of the displaced mass (Slocum: 0.5 %, Seaglider: 1.5 %); a range beyond
    :data:`PUMP_FRACTION_MAX` of the vehicle's mass cannot be physical and is refused with the unit it was
    probably typed in.
    """
    act = acts.get("m0")
    if act is None:
        return
    mass = values.get("m", values.get("mass", values.get("m1")))
    if mass is None:
        return
    reach = max((abs(v) for v in (act.min, act.max, act.fixed) if v is not None and math.isfinite(v)), default=0.0)
    if reach > PUMP_FRACTION_MAX * mass:
        raise VehicleFileError(
            f"{where}: actuator 'm0' reaches {reach:g} kg, {100 * reach / mass:.0f} % of the vehicle's {mass:g} kg: "
            "no buoyancy pump moves more water than the vehicle weighs (real ones move a few percent). Was the range "
            "typed in cm^3 or grams? Give it in kg (350 cm^3 of sea water is about 0.35 kg)")


def _check_hull(values: Mapping[str, float], path: str) -> None:
    """The hull and water keys against each other: a sea-water density, and a hull whose displaced water weighs
    about what the vehicle does (within :data:`HULL_MASS_RATIO`), so that a volume or density in another unit is
    caught at loading."""
    lo, hi = DENSITY_RANGE
    rho = values.get("density")
    if rho is not None and not lo <= rho <= hi:
        hint = " (g/cm^3? give kg/m^3: 1.025 g/cm^3 = 1025 kg/m^3)" if rho < 2 else ""
        raise VehicleFileError(f"{path}: [hydrodynamics] density = {rho:g} kg/m^3 is not sea water ({lo:g}-{hi:g} "
                               f"kg/m^3){hint}")
    mass, volume = values.get("mass", values.get("m")), values.get("volume")
    if mass is not None and volume is not None:
        ratio = (rho or DEFAULT_DENSITY) * volume / mass
        if not HULL_MASS_RATIO[0] <= ratio <= HULL_MASS_RATIO[1]:
            raise VehicleFileError(
                f"{path}: [hydrodynamics] volume = {volume:g} m^3 displaces {ratio:.3g} times the vehicle's mass "
                f"{mass:g} kg: a glider is within a few percent of neutral. Is the volume in litres or cm^3 (give "
                "m^3: 68 L = 0.068 m^3)?")


def _check_consistency(kind: str, values: Mapping[str, float], path: str, law: str = "thesis") -> None:
    """Required keys and the mass model (the checks that need the whole parameter set)."""
    spec = _key_specs(kind, law, path)
    missing = [k for k, s in spec.items() if s.required and k not in values]
    if missing:
        which = f"the '{law}' law of " if law != "thesis" else ""
        raise VehicleFileError(f"{path}: missing required parameter(s) {', '.join(missing)} for {which}a {kind} "
                               "vehicle")
    _check_hull(values, path)
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
        # one damping convention (docs/conventions.md): the linear rate damping about each body axis is given either
        # V^2-scaled (K_qi, (2.12)-(2.14)) or without V^2 (K_Omega1_i, chapter 8), never both: no conversion between
        # the two exists (they differ away from one speed), so both nonzero would count the term twice
        for axis, (kq, k1) in (("roll", ("K_q1", "K_Omega1_1")), ("pitch", ("K_q", "K_Omega1_2")),
                               ("yaw", ("K_q3", "K_Omega1_3"))):
            if values.get(kq, 0.0) != 0.0 and values.get(k1, 0.0) != 0.0:
                raise VehicleFileError(
                    f"{path}: {axis} damping is given twice, as {kq} = {values[kq]:g} kg s/rad (times V^2, "
                    f"(2.12)-(2.14)) and as {k1} = {values[k1]:g} kg m^2 s/rad (chapter 8, no V^2); both act on the "
                    f"same linear rate term and would be counted twice. Keep one and set the other to 0 "
                    "(docs/conventions.md, 'Damping: one convention')")


def _actuator_from_entry(name: str, entry: dict[str, Any], where: str, require_source: bool = True) -> Actuator:
    """An :class:`Actuator` from one ``[actuators]`` entry (an inline table), checked."""
    if name not in ACTUATOR_SPECS:
        hint = f" ({name} is a parameter, not an actuator)" if name in _UG else ""
        raise VehicleFileError(f"{where}: unknown actuator '{name}'{hint}; known: {', '.join(ACTUATOR_SPECS)}")
    if not isinstance(entry, dict):
        raise VehicleFileError(f"{where}: actuator '{name}' must be an inline table such as "
                               f"{{ min = ..., max = ..., rate = ..., unit = \"...\", source = \"...\" }}, got "
                               f"{entry!r}")
    bad = set(entry) - _ACTUATOR_FIELDS
    if bad:
        raise VehicleFileError(f"{where}: actuator '{name}' has unknown field(s) {sorted(bad)}; allowed: "
                               f"{sorted(_ACTUATOR_FIELDS)}")
    if require_source and not (isinstance(entry.get("source"), str) and entry["source"].strip()):
        raise VehicleFileError(f"{where}: actuator '{name}' needs a non-empty 'source'")
    if require_source and "unit" not in entry:
        raise VehicleFileError(f"{where}: actuator '{name}' needs a 'unit' ('{ACTUATOR_SPECS[name].unit}')")
    if "fixed" in entry and "rate" in entry:
        raise VehicleFileError(f"{where}: actuator '{name}' is fixed (fixed = {entry['fixed']!r}); it cannot have "
                               "a 'rate'")
    if not ({"min", "max", "fixed"} & set(entry)):
        raise VehicleFileError(f"{where}: actuator '{name}' needs a range (min, max) or a fixed value")
    if "fixed" not in entry and not {"min", "max"} <= set(entry):
        raise VehicleFileError(f"{where}: actuator '{name}' needs both 'min' and 'max'")
    for k in ("unit", "source", "note"):
        if k in entry and not isinstance(entry[k], str):
            raise VehicleFileError(f"{where}: actuator '{name}': '{k}' must be a string, got {entry[k]!r}")
    try:
        return Actuator(name=name, min=entry.get("min", -math.inf), max=entry.get("max", math.inf),
                        rate=entry.get("rate", math.inf), fixed=entry.get("fixed"), unit=entry.get("unit", ""),
                        source=entry.get("source", ""), note=entry.get("note", ""))
    except VehicleFileError as exc:
        raise VehicleFileError(f"{where}: {exc}") from None


def _check_actuators(kind: str, actuators: Mapping[str, Any], values: Mapping[str, float],
                     where: str) -> dict[str, Actuator]:
    """Actuator entries checked against the kind and the nominal parameters (``m0``, ``r_P*``)."""
    out: dict[str, Actuator] = {}
    if actuators and kind != "underwater_glider":
        raise VehicleFileError(f"{where}: an [actuators] table is defined for underwater gliders only, not {kind}")
    for name, act in actuators.items():
        if isinstance(act, Mapping) and not isinstance(act, Actuator):
            act = _actuator_from_entry(str(name), dict(act), where, require_source=False)
        if not isinstance(act, Actuator) or act.name != name:
            raise VehicleFileError(f"{where}: actuator entry {name!r} must be an Actuator named {name!r}")
        if name in values:
            v = values[name]
            if act.fixed is not None and v != act.fixed:
                raise VehicleFileError(
                    f"{where}: parameter '{name}' = {v:g} and [actuators] {name} fixed = {act.fixed:g} disagree; "
                    "give the setting once (the fixed actuator value)")
            if act.fixed is None and not act.contains(v):
                raise VehicleFileError(
                    f"{where}: nominal parameter '{name}' = {v:g} {act.unit} is outside the actuator range "
                    f"[{act.min:g}, {act.max:g}] {act.unit} of [actuators] {name}")
        out[name] = act
    _check_roll_and_rudder(out, values, where)
    return out


def _check_roll_and_rudder(acts: Mapping[str, Actuator], values: Mapping[str, float], where: str) -> None:
    """A ``roll`` actuator rotates the battery about body-1 (``r_P2 = rho sin phi``, ``r_P3 = rho cos phi``): it
    needs a battery offset ``rho = r_P3`` that does not translate and no lateral translation besides; a ``rudder``
    needs the side-force and yaw-moment coefficients that make it act."""
    if "roll" in acts:
        for axis in ("r_P2", "r_P3"):
            a = acts.get(axis)
            if a is not None and a.fixed is None:
                raise VehicleFileError(
                    f"{where}: [actuators] roll rotates the battery about body-1 (r_P2 = rho sin(phi), r_P3 = rho "
                    f"cos(phi)), so {axis} cannot also translate; make {axis} fixed (r_P3 fixed is the offset rho)")
        r2 = acts["r_P2"].fixed if "r_P2" in acts else values.get("r_P2", 0.0)
        if r2 != 0.0:
            raise VehicleFileError(f"{where}: [actuators] roll puts the battery at r_P2 = rho sin(phi); a fixed "
                                   f"lateral offset r_P2 = {r2:g} m besides is not modelled; set r_P2 to 0")
        rho = acts["r_P3"].fixed if "r_P3" in acts else values.get("r_P3")
        if rho is None or not rho > 0:
            raise VehicleFileError(f"{where}: [actuators] roll needs the battery offset below the body-1 axis, "
                                   f"rho = r_P3 > 0 (m), as a fixed [actuators] r_P3 or a parameter; got {rho!r}")
    if "rudder" in acts and acts["rudder"].fixed is None:
        missing = [k for k in ("K_SF_rudder", "K_MY_rudder") if k not in values]
        if missing:
            raise VehicleFileError(f"{where}: [actuators] rudder needs the rudder coefficients {missing} in "
                                   "[parameters] (side force K_SF_rudder, kg/m/rad, and yaw moment K_MY_rudder, "
                                   "kg/rad, per rudder angle)")


def _vehicle_from_plain(name: str, kind: str, title: str, params: dict[str, float], sources: dict[str, str],
                        path: str, overrides: dict[str, float], notes: str,
                        actuators: dict[str, dict[str, Any]] | None = None, law: str = "thesis",
                        density_profile: tuple[Any, ...] = (), uncertainty: dict[str, dict[str, Any]] | None = None,
                        correlation: tuple[Any, ...] = ()) -> Vehicle:
    acts = {k: Actuator(**a) for k, a in (actuators or {}).items()}
    table = {k: Uncertainty(**u) for k, u in (uncertainty or {}).items()}
    return Vehicle(name=name, kind=kind, title=title, params=MappingProxyType(params),
                   sources=MappingProxyType(sources), path=path, overrides=MappingProxyType(overrides),
                   notes=notes, actuators=MappingProxyType(acts), law=law, density_profile=density_profile,
                   uncertainty=MappingProxyType(table), correlation=correlation)


def _build_vehicle(name: str, kind: str, title: str, values: dict[str, float], sources: dict[str, str],
                   path: str, all_overrides: dict[str, float], notes: str,
                   new_overrides: Mapping[str, float], actuators: dict[str, Actuator] | None = None,
                   law: str = "thesis", density_profile: tuple[Any, ...] = (),
                   uncertainty: Mapping[str, Uncertainty] | None = None, correlation: tuple[Any, ...] = ()) -> Vehicle:
    spec = _key_specs(kind, law, path)
    for key, val in new_overrides.items():
        if key in _MOVED_KEYS:
            raise VehicleFileError(f"override '{key}': actuator limits are set with "
                                   f"Vehicle.with_actuators(), e.g. {_MOVED_KEYS[key]}")
        if key not in spec:
            raise VehicleFileError(f"override for {path}: {_unknown_key(key, kind, law)}")
        values[key] = _check_value(key, val, spec[key], f"override for {path}")
        sources[key] = "override"
    all_overrides = {k: (values[k] if k in new_overrides else v) for k, v in all_overrides.items()}
    _check_consistency(kind, values, path, law)
    table, corr = keep_contained(uncertainty or {}, correlation, values) if new_overrides else (uncertainty or {},
                                                                                               correlation)
    return Vehicle(name=name, kind=kind, title=title, params=MappingProxyType(dict(values)),
                   sources=MappingProxyType(dict(sources)), path=path,
                   overrides=MappingProxyType(dict(all_overrides)), notes=notes,
                   actuators=MappingProxyType(dict(actuators or {})), law=law, density_profile=density_profile,
                   uncertainty=MappingProxyType(dict(table)), correlation=corr)


def _line_of(text: str, key: str, table: str) -> str:
    """`` (line N)`` of the first ``key = ...`` inside ``[table]`` of ``text``, or ``""``."""
    current = ""
    for n, line in enumerate(text.splitlines(), 1):
        stripped = line.strip()
        if stripped.startswith("[") and "]" in stripped:
            current = stripped[1:stripped.index("]")].strip()
        elif current == table and re.match(rf'^\s*"?{re.escape(key)}"?\s*=', line):
            return f" (line {n})"
    return ""


def _parse_entries(table: dict[str, Any], spec: Mapping[str, ParamSpec], where: str, text: str, name: str,
                   unknown: Any) -> tuple[dict[str, float], dict[str, str]]:
    """Values and sources of the ``{ value, unit, source }`` entries of ``[name]``, each checked against ``spec``.

    ``unknown(key)`` gives the message for a key ``spec`` does not know; the key's line is appended.
    """
    values: dict[str, float] = {}
    sources: dict[str, str] = {}
    for key, entry in table.items():
        if key in _MOVED_KEYS:
            raise VehicleFileError(f"{where}: parameter '{key}' moved to the [actuators] table: write "
                                   f"[actuators] {_MOVED_KEYS[key]}")
        if key not in spec:
            raise VehicleFileError(f"{where}{_line_of(text, key, name)}: [{name}] {unknown(key)}")
        if not isinstance(entry, dict) or set(entry) - {"value", "unit", "source", "note"} or not {
                "value", "unit", "source"} <= set(entry):
            raise VehicleFileError(
                f"{where}: parameter '{key}' must be an inline table {{ value = ..., unit = \"...\", "
                f"source = \"...\" }} (optional 'note'), got {entry!r}")
        if not all(isinstance(entry[k], str) for k in ("unit", "source", "note") if k in entry):
            raise VehicleFileError(f"{where}: parameter '{key}': 'unit', 'source' and 'note' must be strings, got "
                                   f"{entry!r}")
        unit = entry["unit"]
        if _norm_unit(unit) != _norm_unit(spec[key].unit):
            raise VehicleFileError(
                f"{where}{_line_of(text, key, name)}: parameter '{key}' has unit '{unit}', glidectl expects "
                f"'{spec[key].unit}' (SI, angles in rad unless the law says otherwise): convert the value")
        if not str(entry["source"]).strip():
            raise VehicleFileError(f"{where}: parameter '{key}' needs a non-empty 'source'")
        values[key] = _check_value(key, entry["value"], spec[key], where)
        sources[key] = str(entry["source"])
    return values, sources


def _parse_profile(table: Any, where: str) -> tuple[tuple[Any, ...], tuple[str, ...]]:
    """``[hydrodynamics.density_profile]``: ``depth`` and ``density`` entries ``{ values = [...], unit, source }``."""
    if not isinstance(table, dict) or set(table) != {"depth", "density"}:
        raise VehicleFileError(f"{where}: [hydrodynamics.density_profile] needs exactly the entries 'depth' and "
                               "'density', each { values = [...], unit = \"...\", source = \"...\" }")
    out, sources = [], []
    for key, unit in (("depth", "m"), ("density", "kg/m^3")):
        entry = table[key]
        if not isinstance(entry, dict) or set(entry) - {"values", "unit", "source", "note"} or not {
                "values", "unit", "source"} <= set(entry) or not isinstance(entry["values"], list):
            raise VehicleFileError(f"{where}: density_profile '{key}' must be {{ values = [...], unit = \"{unit}\", "
                                   f"source = \"...\" }}, got {entry!r}")
        if not isinstance(entry["unit"], str) or _norm_unit(entry["unit"]) != _norm_unit(unit):
            raise VehicleFileError(f"{where}: density_profile '{key}' has unit {entry['unit']!r}, glidectl expects "
                                   f"'{unit}'")
        if not all(_is_real(v) for v in entry["values"]):
            raise VehicleFileError(f"{where}: density_profile '{key}' values must be real numbers")
        out.append(entry["values"])
        sources.append(str(entry["source"]))
    return tuple(out), tuple(sources)


def _parse_law(doc: dict[str, Any], kind: str, where: str,
               text: str) -> tuple[str, dict[str, Any], tuple[Any, ...], tuple[str, ...]]:
    """The ``[hydrodynamics]`` table: the law's name (``"thesis"`` without the table), its entries, the density
    profile (``()`` without one) and the sources of its depths and densities."""
    hyd = doc.get("hydrodynamics", {})
    if not isinstance(hyd, dict):
        raise VehicleFileError(f"{where}: [hydrodynamics] must be a table")
    hyd = dict(hyd)
    profile, source = _parse_profile(hyd.pop("density_profile"), where) if "density_profile" in hyd else ((), ())
    law = hyd.pop("law", "thesis")
    if not isinstance(law, str) or law not in HYDRO_SPECS:
        raise VehicleFileError(f"{where}{_line_of(text, 'law', 'hydrodynamics')}: [hydrodynamics] {_unknown_law(law)}")
    if kind != "underwater_glider" and (law != "thesis" or hyd or profile):
        raise VehicleFileError(f"{where}: a [hydrodynamics] table is defined for underwater gliders only, not {kind}")
    return law, hyd, profile, source


def _parse(text: str, where: str) -> tuple[str, str, str, str, dict[str, float], dict[str, str],
                                          dict[str, Actuator], str, tuple[Any, ...], dict[str, Uncertainty],
                                          tuple[Any, ...]]:
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise VehicleFileError(f"{where}: not valid TOML: {exc}") from None
    except RecursionError:
        raise VehicleFileError(f"{where}: not a usable TOML file (nested too deeply)") from None
    tables = ("vehicle", "parameters", "actuators", "hydrodynamics", "uncertainty")
    unknown_top = set(doc) - set(tables)
    if unknown_top:
        near = [m for t in sorted(unknown_top) for m in difflib.get_close_matches(t, tables, n=1)]
        hint = f" (did you mean [{near[0]}]?)" if near else ""
        raise VehicleFileError(f"{where}: unknown top-level table(s) {sorted(unknown_top)}{hint}; "
                               "expected [vehicle], [parameters] and optionally [actuators], [hydrodynamics], "
                               "[uncertainty]")
    head = doc.get("vehicle")
    if not isinstance(head, dict):
        raise VehicleFileError(f"{where}: missing [vehicle] table")
    bad = set(head) - _HEADER_KEYS
    if bad:
        raise VehicleFileError(f"{where}: unknown key(s) {sorted(bad)} in [vehicle]; allowed: {sorted(_HEADER_KEYS)}")
    for k in ("name", "kind"):
        if not isinstance(head.get(k), str):
            raise VehicleFileError(f"{where}: [vehicle] needs a string '{k}'")
    for k in ("title", "source", "notes"):
        if k in head and not isinstance(head[k], str):
            raise VehicleFileError(f"{where}: [vehicle] '{k}' must be a string, got {head[k]!r}")
    kind = head["kind"]
    if kind not in PARAMETER_SPECS:
        raise VehicleFileError(f"{where}: unknown vehicle kind '{kind}'; expected one of {sorted(PARAMETER_SPECS)}")
    table = doc.get("parameters")
    if not isinstance(table, dict):
        raise VehicleFileError(f"{where}: missing [parameters] table")
    law, hyd, profile, profile_source = _parse_law(doc, kind, where, text)
    spec = _key_specs(kind, law, where)
    hydro_keys = set(HYDRO_SPECS[law]) if kind == "underwater_glider" else set()
    param_spec = {k: v for k, v in spec.items() if k not in hydro_keys}
    values, sources = _parse_entries(
        table, param_spec, where, text, "parameters",
        lambda key: (f"'{key}' belongs in [hydrodynamics]" if key in hydro_keys
                     else _unknown_key(key, kind, law)))
    hyd_values, hyd_sources = _parse_entries(
        hyd, {k: spec[k] for k in hydro_keys}, where, text, "hydrodynamics",
        lambda key: (f"'{key}' belongs in [parameters]" if key in param_spec else _unknown_key(key, kind, law)))
    values.update(hyd_values)
    sources.update(hyd_sources)
    for key, src in zip(("depth", "density"), profile_source, strict=False):
        sources[f"density_profile.{key}"] = src
    if str(head.get("source", "")).strip():
        sources[FILE_SOURCE_KEY] = str(head["source"])      # the file's own source, beside the values' sources
    acts_table = doc.get("actuators", {})
    if not isinstance(acts_table, dict):
        raise VehicleFileError(f"{where}: [actuators] must be a table")
    actuators = {str(k): _actuator_from_entry(str(k), v, where) for k, v in acts_table.items()}
    table, corr = _parse_uncertainty(doc, values, kind, law, actuators, where)
    return (head["name"], kind, str(head.get("title", head["name"])), str(head.get("notes", "")), values, sources,
            actuators, law, profile, table, corr)


def _parse_uncertainty(doc: dict[str, Any], values: Mapping[str, float], kind: str, law: str,
                       actuators: Mapping[str, Actuator], where: str) -> tuple[dict[str, Uncertainty], Any]:
    """The ``[uncertainty]`` table (with its ``correlation`` sub-table), resolved against the file's values."""
    table = doc.get("uncertainty", {})
    if not isinstance(table, dict):
        raise VehicleFileError(f"{where}: [uncertainty] must be a table")
    table = dict(table)
    correlation = table.pop("correlation", None)
    if correlation is not None and not isinstance(correlation, dict):
        raise VehicleFileError(f"{where}: [uncertainty.correlation] must be a table such as \"K_L,K_D\" = 0.6")
    nominal = {**(GLIDERFLIGHT_DEFAULTS if law == "gliderflight" else {}), **values}
    return _check_uncertainty(table, correlation, nominal, kind, law, actuators, where, None)


def _read_file(s: str) -> tuple[str, str]:
    """Text of the vehicle file ``s`` (a regular UTF-8 file of at most MAX_FILE_BYTES) and its name."""
    p = Path(s)
    problem = ""
    try:
        exists = p.exists()
        regular = exists and p.is_file()
    except (OSError, ValueError) as exc:  # ValueError: an embedded NUL byte in the path
        raise VehicleFileError(f"cannot read vehicle file {s!r}: {getattr(exc, 'strerror', None) or exc}") from None
    if not s or (not p.suffix and not exists):
        problem = f"no preset or file named '{s}'; presets: {', '.join(list_presets())}"
    elif exists and not regular:
        problem = f"vehicle file '{p}' is not a regular file"
    if problem:
        raise VehicleFileError(problem)
    try:
        with p.open("rb") as fh:
            data = fh.read(MAX_FILE_BYTES + 1)
    except (OSError, ValueError) as exc:  # ValueError: an embedded NUL byte in the path
        raise VehicleFileError(f"cannot read vehicle file {s!r}: {getattr(exc, 'strerror', None) or exc}") from None
    if len(data) > MAX_FILE_BYTES:
        raise VehicleFileError(f"vehicle file '{p}' is larger than {MAX_FILE_BYTES} bytes; vehicle files are "
                               "small TOML files")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise VehicleFileError(f"vehicle file '{p}' is not UTF-8 text (byte {exc.start}: {exc.reason}); save "
                               "it as UTF-8 TOML") from None
    return text, str(p)


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
    ArgumentTypeError
        ``name_or_path`` is not a ``str`` or a path.
    VehicleFileError
        Unknown preset, a file that cannot be read, is not a regular file, is larger than :data:`MAX_FILE_BYTES`
        or is not UTF-8; invalid TOML; unknown/missing keys, wrong units, values that are not finite real numbers,
        out of their sign constraint or plausibility limits (:data:`VALUE_MAX`, :data:`POSITIVE_MIN`); the same for
        the overrides; an invalid ``[uncertainty]`` table (:mod:`glidectl.uncertainty`).

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("rogue")
    >>> veh.name, veh.kind, veh.params["mbar"]
    ('rogue', 'underwater_glider', 2.0)
    >>> gc.load_vehicle("rogue", K_M=-40.0).params["K_M"]  # an override, validated like the file
    -40.0
    """
    if not isinstance(name_or_path, str | os.PathLike):
        raise ArgumentTypeError(f"name_or_path must be a preset name (str) or a path, got "
                                f"{type(name_or_path).__name__} {name_or_path!r}; presets: "
                                f"{', '.join(list_presets())}")
    s = os.fspath(name_or_path)
    if not isinstance(s, str):  # a bytes path
        raise ArgumentTypeError(f"name_or_path must be a str or a str path, got {type(s).__name__} {s!r}")
    if s in list_presets():
        res = _presets_dir() / f"{s}.toml"
        text, where = res.read_text(encoding="utf-8"), f"preset '{s}'"
    else:
        text, where = _read_file(s)
    name, kind, title, notes, values, sources, actuators, law, profile, table, corr = _parse(text, where)
    return _build_vehicle(name, kind, title, values, sources, where, dict(overrides), notes, overrides, actuators,
                          law, profile, table, corr)
