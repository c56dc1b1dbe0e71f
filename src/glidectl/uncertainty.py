"""Coefficient uncertainty of a vehicle: the ``[uncertainty]`` table of a vehicle file, its checks, and the draws
behind :meth:`glidectl.Vehicle.sample` and :meth:`glidectl.Vehicle.vertices`.

The table
---------
An optional ``[uncertainty]`` table gives, for some keys of the vehicle's parameters (``[parameters]`` and the
``[hydrodynamics]`` law and hull coefficients: every key of ``veh.params``), how well the value is known. Each entry
is an inline table in one of these forms (values in the parameter's unit)::

    [uncertainty]
    K_M  = { min = -60.0, max = -40.0, source = "..." }   # interval: uniform on [min, max]
    K_D0 = { rel = 0.3, source = "..." }                 # interval nominal -+ |nominal| * 0.3
    K_L  = { std = 2.0, source = "..." }                 # normal, absolute standard deviation
    K_D  = { rel_std = 0.3, min = 0.0, source = "..." }  # normal, std = |nominal| * 0.3, truncated below at 0

    [uncertainty.correlation]
    "K_L,K_D" = 0.6                                      # correlation between two normal entries

An interval must contain the nominal value; a normal entry is centred on it and may be truncated by ``min`` and/or
``max`` (which must then contain the nominal too). Bounds respect the parameter's sign constraint (a mass interval
cannot reach 0) and, like standard deviations, the plausibility limit :data:`glidectl.params.VALUE_MAX`; the tails
of an untruncated normal may cross the sign constraint, and a sample there is reported as invalid by
:meth:`~glidectl.Vehicle.sample`. Relative forms (``rel``, ``rel_std``) are resolved against the nominal value when
the table is read (by :func:`~glidectl.load_vehicle` or :meth:`~glidectl.Vehicle.with_uncertainty`) and stored as
absolute values (:class:`Uncertainty`), which :meth:`~glidectl.Vehicle.to_toml` writes back. Correlations are
between normal entries, in ``[-1, 1]``; with the unit variances of the normal entries they must form a positive
semidefinite matrix. Actuated settings (their range is in ``[actuators]``) and the setting of a fixed actuator take
no entry.

Sampling
--------
Sample ``i`` of :func:`draw_values` comes from its own stream, ``numpy.random.default_rng`` seeded with child ``i``
of ``numpy.random.SeedSequence(seed).spawn(n)``: the first ``m`` samples of ``n > m`` draws equal the ``m`` draws
with the same seed. Intervals are uniform; untruncated or correlated normals are ``nominal + std * (L z)`` with
``L`` the Cholesky factor of the correlation matrix of the normal entries; a truncated normal without correlation
is drawn by inverse CDF within its bounds, a correlated one by redrawing the correlated vector until every truncated
entry lies within its bounds.
"""

from __future__ import annotations

import difflib
import math
import numbers
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, replace
from typing import Any, Literal

import numpy as np
from scipy.special import ndtr, ndtri

from .errors import ArgumentError, VehicleFileError

__all__ = ["CORRELATION_TOL", "MAX_REJECTIONS", "UNCERTAINTY_FIELDS", "VERTEX_STDS", "Uncertainty",
           "check_uncertainty", "correlation_matrix", "draw_values", "keep_contained", "vertex_values"]

#: Fields an entry of the ``[uncertainty]`` table may have.
UNCERTAINTY_FIELDS = ("min", "max", "std", "rel_std", "rel", "source")
#: Most negative eigenvalue accepted in the correlation matrix of the normal entries (rounding of given values).
CORRELATION_TOL = 1e-10
#: Standard deviations either side of the nominal value that :func:`vertex_values` takes for an untruncated normal.
VERTEX_STDS = 3.0
#: Draws of a correlated vector with truncated entries tried per sample before :func:`draw_values` gives up.
MAX_REJECTIONS = 10_000

Correlation = tuple[tuple[tuple[str, str], float], ...]


def _real(value: Any) -> bool:
    """A Python or numpy real scalar, never a bool."""
    return isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_)


@dataclass(frozen=True, eq=False)
class Uncertainty:
    """How well one vehicle coefficient is known: an entry of the ``[uncertainty]`` table, in absolute terms.

    Parameters
    ----------
    kind : {"interval", "normal"}
        Uniform on ``[low, high]``, or normal about the nominal value with standard deviation ``std``.
    low, high : float
        Bounds in the parameter's unit: the interval (finite), or the truncation of a normal (``-inf``/``inf``
        where untruncated).
    std : float, optional
        Standard deviation of a normal entry (parameter's unit, > 0); ``nan`` for an interval.
    source : str, optional
        Where the uncertainty comes from.

    Raises
    ------
    VehicleFileError
        An unknown kind, bounds that are not real numbers or not ``low < high``, an interval with an infinite
        bound or a ``std``, a normal entry whose ``std`` is not a finite number > 0, a source that is not a string.

    Attributes
    ----------
    kind : str
        ``"interval"`` or ``"normal"``.
    low, high : float
        Absolute bounds (parameter's unit).
    std : float
        Absolute standard deviation (``nan`` for an interval).
    source : str
        Where the uncertainty comes from.

    Notes
    -----
    Two entries are equal when every field is (``nan`` standard deviations compare equal).
    """

    kind: Literal["interval", "normal"]
    low: float
    high: float
    std: float = math.nan
    source: str = ""

    def __post_init__(self) -> None:
        if self.kind not in ("interval", "normal"):
            raise VehicleFileError(f"uncertainty kind must be 'interval' or 'normal', got {self.kind!r}")
        for name in ("low", "high", "std"):
            value = getattr(self, name)
            if not _real(value) or (math.isnan(float(value)) and name != "std"):
                raise VehicleFileError(f"uncertainty '{name}' must be a real number, got {value!r}")
            object.__setattr__(self, name, float(value))
        if not isinstance(self.source, str):
            raise VehicleFileError(f"uncertainty 'source' must be a string, got {self.source!r}")
        if not self.low < self.high:
            raise VehicleFileError(f"uncertainty bounds must satisfy min < max, got min = {self.low:g}, "
                                   f"max = {self.high:g}")
        if self.kind == "interval":
            if not (math.isfinite(self.low) and math.isfinite(self.high)):
                raise VehicleFileError(f"an uncertainty interval needs finite bounds, got [{self.low:g}, "
                                       f"{self.high:g}]")
            if not math.isnan(self.std):
                raise VehicleFileError(f"an uncertainty interval has no std (got {self.std:g}); give a normal entry")
        elif not (math.isfinite(self.std) and self.std > 0):
            raise VehicleFileError(f"a normal uncertainty needs a finite std > 0, got {self.std!r}")

    def _key(self) -> tuple[Any, ...]:
        return (self.kind, self.low, self.high, None if math.isnan(self.std) else self.std, self.source)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Uncertainty) and self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    @property
    def truncated(self) -> bool:
        """True for a normal entry with a finite ``min`` or ``max``."""
        return self.kind == "normal" and (math.isfinite(self.low) or math.isfinite(self.high))

    def contains(self, value: float) -> bool:
        """Whether ``value`` (parameter's unit) lies within ``[low, high]``."""
        return bool(self.low <= value <= self.high)

    def box(self, nominal: float) -> tuple[float, float]:
        """The range :func:`vertex_values` spans: the interval, or a normal's truncation bounds where finite and
        ``nominal -+ VERTEX_STDS * std`` where not (parameter's unit)."""
        if self.kind == "interval":
            return self.low, self.high
        lo = self.low if math.isfinite(self.low) else nominal - VERTEX_STDS * self.std
        hi = self.high if math.isfinite(self.high) else nominal + VERTEX_STDS * self.std
        return lo, hi

    def as_entry(self) -> dict[str, Any]:
        """The fields of the entry as a vehicle file writes it (absolute form): ``min``/``max`` for an interval,
        ``std`` and the finite truncation bounds for a normal, and ``source``."""
        out: dict[str, Any] = {} if self.kind == "interval" else {"std": self.std}
        out.update({name: v for name, v in (("min", self.low), ("max", self.high)) if math.isfinite(v)})
        out["source"] = self.source
        return out

    def as_plain(self) -> dict[str, Any]:
        """Plain dict of the fields (for pickling and JSON)."""
        return {"kind": self.kind, "low": self.low, "high": self.high, "std": self.std, "source": self.source}

    def describe(self) -> str:
        """One-line summary such as ``uniform [-60, -40]`` or ``normal std 2 within [0, inf]``."""
        if self.kind == "interval":
            return f"uniform [{self.low:.6g}, {self.high:.6g}]"
        trunc = f" within [{self.low:.6g}, {self.high:.6g}]" if self.truncated else ""
        return f"normal std {self.std:.6g}{trunc}"


def _number(label: str, name: str, value: Any) -> float:
    if not _real(value):
        raise VehicleFileError(f"{label}: '{name}' must be a real number, got {type(value).__name__} {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise VehicleFileError(f"{label}: '{name}' must be finite, got {value!r}")
    return v


def _positive(label: str, name: str, value: float) -> float:
    if not value > 0:
        raise VehicleFileError(f"{label}: '{name}' must be > 0, got {value:g}")
    return value


def _resolve(entry: Mapping[Any, Any], nominal: float, label: str, source: Any) -> Uncertainty:
    """An :class:`Uncertainty` from one entry in the file's form (absolute or relative), checked."""
    bad = [f for f in entry if f not in UNCERTAINTY_FIELDS]
    if bad:
        near = difflib.get_close_matches(str(bad[0]), UNCERTAINTY_FIELDS, n=1)
        hint = f" (did you mean '{near[0]}'?)" if near else ""
        raise VehicleFileError(f"{label}: unknown field(s) {sorted(map(str, bad))}{hint}; allowed: "
                               f"{', '.join(UNCERTAINTY_FIELDS)}")
    if not isinstance(source, str):
        raise VehicleFileError(f"{label}: 'source' must be a string, got {source!r}")
    num = {f: _number(label, f, entry[f]) for f in ("min", "max", "std", "rel_std", "rel") if f in entry}
    if "std" in num and "rel_std" in num:
        raise VehicleFileError(f"{label}: give 'std' (absolute) or 'rel_std' (relative to the nominal), not both")
    low, high, std = num.get("min", -math.inf), num.get("max", math.inf), math.nan
    kind: Literal["interval", "normal"] = "interval"
    if "std" in num or "rel_std" in num:
        if "rel" in num:
            raise VehicleFileError(f"{label}: 'rel' makes an interval; a normal entry ('std' or 'rel_std') is "
                                   "truncated with 'min'/'max'")
        kind = "normal"
        std = _positive(label, "std", num["std"]) if "std" in num else \
            abs(nominal) * _positive(label, "rel_std", num["rel_std"])
        if std == 0:
            raise VehicleFileError(f"{label}: 'rel_std' of the nominal value 0 gives no spread; give 'std'")
    elif "rel" in num:
        if "min" in num or "max" in num:
            raise VehicleFileError(f"{label}: 'rel' and 'min'/'max' both give the interval; give one of them")
        half = abs(nominal) * _positive(label, "rel", num["rel"])
        if half == 0:
            raise VehicleFileError(f"{label}: 'rel' of the nominal value 0 gives an empty interval; give min and max")
        low, high = nominal - half, nominal + half
    elif not ("min" in num and "max" in num):
        raise VehicleFileError(f"{label}: give an interval (min and max, or rel) or a normal (std or rel_std, "
                               f"optional min/max), got {dict(entry)!r}")
    if not low < high:
        raise VehicleFileError(f"{label}: min = {low:g} must be < max = {high:g}")
    return Uncertainty(kind, low, high, std, source)


def _check_entry(key: str, unc: Uncertainty, nominal: float, constraint: str, label: str, value_max: float) -> None:
    """Bounds against the nominal value, the parameter's sign constraint and the plausibility limit."""
    for name, v in (("min", unc.low), ("max", unc.high), ("std", unc.std)):
        if math.isfinite(v) and abs(v) > value_max:
            raise VehicleFileError(f"{label}: {name} = {v:g} is beyond the plausibility limit {value_max:g} (SI "
                                   "units); check the unit")
    if not unc.contains(nominal):
        what = "interval" if unc.kind == "interval" else "truncation"
        raise VehicleFileError(f"{label}: the {what} [{unc.low:g}, {unc.high:g}] excludes the nominal value "
                               f"{nominal:g}; an uncertainty is about the vehicle's value")
    if math.isfinite(unc.low) and ((constraint == "positive" and not unc.low > 0)
                                   or (constraint == "nonnegative" and not unc.low >= 0)):
        sign = "> 0" if constraint == "positive" else ">= 0"
        raise VehicleFileError(f"{label}: min = {unc.low:g} is outside the values '{key}' can take ({sign}); "
                               "narrow the interval (a normal entry's tail may reach there: it counts as an invalid "
                               "sample)")


def check_uncertainty(entries: Any, correlation: Any, nominal: Mapping[str, float], constraints: Mapping[str, str],
                      actuators: Mapping[str, str], where: str, unknown: Callable[[str], str],
                      default_source: str | None,
                      value_max: float = math.inf) -> tuple[dict[str, Uncertainty], Correlation]:
    """The ``[uncertainty]`` table checked against a vehicle: entries resolved to :class:`Uncertainty` objects.

    Parameters
    ----------
    entries : Mapping
        Key -> an inline table in the file's form (see the module docstring) or an :class:`Uncertainty`.
    correlation : Mapping or sequence or None
        ``{"K_L,K_D": 0.6}``, ``{("K_L", "K_D"): 0.6}`` or ``(( ("K_L", "K_D"), 0.6), ...)``.
    nominal : Mapping[str, float]
        The vehicle's parameter values (the nominal values), in the order entries are returned.
    constraints : Mapping[str, str]
        Sign constraint (``"positive"``, ``"nonnegative"``, ``"any"``) of every key the vehicle may define.
    actuators : Mapping[str, str]
        ``"actuated"`` or ``"fixed"`` for each actuator of the vehicle (these keys take no entry).
    where : str
        The file or vehicle, for messages.
    unknown : callable
        Message for a key the vehicle does not know (with a "did you mean").
    default_source : str or None
        Source of an entry without one; ``None``: a non-empty ``source`` is required.
    value_max : float, optional
        Largest magnitude of a bound or standard deviation (the parameters' plausibility limit).

    Returns
    -------
    (dict, tuple)
        Key -> :class:`Uncertainty` (in the order of ``nominal``), and the correlations as a sorted tuple of
        ``((key1, key2), rho)`` with ``key1 < key2``.

    Raises
    ------
    VehicleFileError
        An unknown key, an actuator's key, a key without a value, an invalid entry, or invalid correlations.
    """
    if not isinstance(entries, Mapping):
        raise VehicleFileError(f"{where}: [uncertainty] must be a table of inline tables, got "
                               f"{type(entries).__name__}")
    if not entries and not correlation:
        return {}, ()
    table: dict[str, Uncertainty] = {}
    for key, entry in entries.items():
        label = f"{where}: [uncertainty] '{key}'"
        if not isinstance(key, str) or (key not in constraints and key not in actuators):
            raise VehicleFileError(f"{where}: [uncertainty] {unknown(str(key))}")
        if key in actuators:
            raise VehicleFileError(f"{label} is {'the fixed setting of' if actuators[key] == 'fixed' else 'set by'} "
                                   f"[actuators] {key}: the actuator's range is in [actuators]; [uncertainty] takes "
                                   "coefficients")
        if key not in nominal:
            raise VehicleFileError(f"{label} has no value in this vehicle: give its value in [parameters] (or "
                                   "[hydrodynamics]) first")
        if isinstance(entry, Uncertainty):
            unc = entry
        elif isinstance(entry, Mapping):
            unc = _resolve(entry, nominal[key], label, entry.get("source", ""))
        else:
            raise VehicleFileError(f"{label} must be an inline table such as {{ min = ..., max = ..., "
                                   f"source = \"...\" }} or {{ std = ..., source = \"...\" }}, got {entry!r}")
        if not unc.source.strip():
            if default_source is None:
                raise VehicleFileError(f"{label} needs a non-empty 'source'")
            unc = replace(unc, source=default_source)
        _check_entry(key, unc, nominal[key], constraints.get(key, "any"), label, value_max)
        table[key] = unc
    ordered = {k: table[k] for k in nominal if k in table}
    return ordered, _check_correlation(correlation, ordered, where)


def _pairs(correlation: Any, where: str) -> Iterable[tuple[Any, Any]]:
    if isinstance(correlation, Mapping):
        return correlation.items()
    if isinstance(correlation, list | tuple) and all(isinstance(p, list | tuple) and len(p) == 2
                                                     for p in correlation):
        return correlation
    raise VehicleFileError(f"{where}: [uncertainty.correlation] must be a table such as \"K_L,K_D\" = 0.6, got "
                           f"{correlation!r}")


def _check_correlation(correlation: Any, table: Mapping[str, Uncertainty], where: str) -> Correlation:
    """Correlations between normal entries: a sorted tuple of ``((key1, key2), rho)``, positive semidefinite."""
    if correlation is None or (isinstance(correlation, Mapping | list | tuple) and not correlation):
        return ()
    out: dict[tuple[str, str], float] = {}
    for pair, rho in _pairs(correlation, where):
        keys = [p.strip() for p in pair.split(",")] if isinstance(pair, str) else pair
        label = f"{where}: [uncertainty.correlation] {pair!r}"
        if not (isinstance(keys, list | tuple) and len(keys) == 2 and all(isinstance(k, str) for k in keys)):
            raise VehicleFileError(f"{label} must name two coefficients, as \"K_L,K_D\"")
        a, b = keys
        if a == b:
            raise VehicleFileError(f"{label} names '{a}' twice; a correlation is between two coefficients")
        for k in (a, b):
            if k not in table:
                near = difflib.get_close_matches(k, list(table), n=1)
                hint = f" (did you mean '{near[0]}'?)" if near else ""
                raise VehicleFileError(f"{label}: '{k}'{hint} has no [uncertainty] entry; correlations are between "
                                       "normal entries")
            if table[k].kind != "normal":
                raise VehicleFileError(f"{label}: '{k}' is an interval; correlations are between normal entries")
        r = _number(label, "correlation", rho)
        if not -1.0 <= r <= 1.0:
            raise VehicleFileError(f"{label} = {r:g}: a correlation lies in [-1, 1]")
        key = (a, b) if a < b else (b, a)
        if key in out:
            raise VehicleFileError(f"{label}: the correlation of '{a}' and '{b}' is given twice")
        out[key] = r
    normals = [k for k, u in table.items() if u.kind == "normal"]
    matrix = correlation_matrix(normals, tuple(out.items()))
    low = float(np.linalg.eigvalsh(matrix).min()) if normals else 0.0
    if low < -CORRELATION_TOL:
        given = ", ".join(f"{a},{b} = {r:g}" for (a, b), r in out.items())
        raise VehicleFileError(f"{where}: [uncertainty.correlation] {given} is not positive semidefinite (smallest "
                               f"eigenvalue {low:.3g}): these correlations cannot hold together; weaken some")
    return tuple(sorted(out.items()))


def correlation_matrix(keys: list[str], correlation: Correlation) -> np.ndarray:
    """The correlation matrix of ``keys`` (identity where no correlation is given)."""
    index = {k: i for i, k in enumerate(keys)}
    matrix = np.eye(len(keys))
    for (a, b), r in correlation:
        if a in index and b in index:
            matrix[index[a], index[b]] = matrix[index[b], index[a]] = r
    return matrix


def keep_contained(table: Mapping[str, Uncertainty], correlation: Correlation,
                   values: Mapping[str, float]) -> tuple[dict[str, Uncertainty], Correlation]:
    """The entries (and correlations) that still apply to parameter values ``values``: an entry whose key is gone
    or whose bounds exclude the new value is dropped, with its correlations."""
    kept = {k: u for k, u in table.items() if k in values and u.contains(values[k])}
    return kept, tuple((p, r) for p, r in correlation if p[0] in kept and p[1] in kept)


def _factor(matrix: np.ndarray) -> np.ndarray:
    """A lower factor ``L`` with ``L L^T = matrix``: Cholesky, or the eigen-decomposition for a singular
    (positive semidefinite) matrix."""
    try:
        return np.linalg.cholesky(matrix)
    except np.linalg.LinAlgError:
        w, v = np.linalg.eigh(matrix)
        return v * np.sqrt(np.clip(w, 0.0, None))


@dataclass(frozen=True)
class _Plan:
    """What one draw needs: column indices and parameters of the interval, inverse-CDF and block entries."""

    interval: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    inverse: np.ndarray
    inv_nom: np.ndarray
    inv_std: np.ndarray
    inv_pa: np.ndarray
    inv_pb: np.ndarray
    inv_lo: np.ndarray
    inv_hi: np.ndarray
    block: np.ndarray
    blk_nom: np.ndarray
    blk_std: np.ndarray
    blk_lo: np.ndarray
    blk_hi: np.ndarray
    factor: np.ndarray
    truncated: bool


def _plan(table: Mapping[str, Uncertainty], correlation: Correlation, nominal: Mapping[str, float]) -> _Plan:
    keys = list(table)
    correlated = {k for pair, r in correlation if r != 0 for k in pair}
    interval = [i for i, k in enumerate(keys) if table[k].kind == "interval"]
    inverse = [i for i, k in enumerate(keys) if table[k].truncated and k not in correlated]
    block = [i for i, k in enumerate(keys) if table[k].kind == "normal" and i not in inverse]

    def arr(idx: list[int], f: Callable[[Uncertainty, float], float]) -> np.ndarray:
        return np.array([f(table[keys[i]], nominal[keys[i]]) for i in idx], dtype=float)

    inv_nom, inv_std = arr(inverse, lambda u, m: m), arr(inverse, lambda u, m: u.std)
    inv_lo, inv_hi = arr(inverse, lambda u, m: u.low), arr(inverse, lambda u, m: u.high)
    return _Plan(
        interval=np.array(interval, dtype=int), lo=arr(interval, lambda u, m: u.low),
        hi=arr(interval, lambda u, m: u.high), inverse=np.array(inverse, dtype=int), inv_nom=inv_nom,
        inv_std=inv_std, inv_pa=ndtr((inv_lo - inv_nom) / inv_std), inv_pb=ndtr((inv_hi - inv_nom) / inv_std),
        inv_lo=inv_lo, inv_hi=inv_hi, block=np.array(block, dtype=int),
        blk_nom=arr(block, lambda u, m: m), blk_std=arr(block, lambda u, m: u.std),
        blk_lo=arr(block, lambda u, m: u.low), blk_hi=arr(block, lambda u, m: u.high),
        factor=_factor(correlation_matrix([keys[i] for i in block], correlation)),
        truncated=any(table[keys[i]].truncated for i in block))


def _draw_one(rng: np.random.Generator, plan: _Plan, k: int, keys: tuple[str, ...]) -> np.ndarray:
    """One sample: uniform intervals, inverse-CDF truncated normals, then the (correlated) block."""
    row = np.empty(k)
    row[plan.interval] = plan.lo + (plan.hi - plan.lo) * rng.random(plan.interval.size)
    if plan.inverse.size:
        p = np.clip(plan.inv_pa + (plan.inv_pb - plan.inv_pa) * rng.random(plan.inverse.size), 1e-300,
                    1.0 - 2.0**-53)
        row[plan.inverse] = np.clip(plan.inv_nom + plan.inv_std * ndtri(p), plan.inv_lo, plan.inv_hi)
    if plan.block.size:
        for _ in range(MAX_REJECTIONS):
            x = plan.blk_nom + plan.blk_std * (plan.factor @ rng.standard_normal(plan.block.size))
            if not plan.truncated or np.all((x >= plan.blk_lo) & (x <= plan.blk_hi)):
                break
        else:
            names = [keys[i] for i in plan.block]
            raise ArgumentError(f"no draw of the correlated normal entries {names} fell within their truncation "
                                f"bounds in {MAX_REJECTIONS} tries: widen the bounds or drop the correlation")
        row[plan.block] = x
    return row


def draw_values(table: Mapping[str, Uncertainty], correlation: Correlation, nominal: Mapping[str, float], n: int,
                seed: int) -> tuple[tuple[str, ...], np.ndarray]:
    """``n`` random draws of the uncertain coefficients (see the module docstring for the streams and the laws).

    Parameters
    ----------
    table : Mapping[str, Uncertainty]
        The vehicle's ``[uncertainty]`` entries.
    correlation : tuple
        ``((key1, key2), rho)`` pairs between normal entries.
    nominal : Mapping[str, float]
        Nominal values (the normal entries' means).
    n : int
        Number of samples (>= 1).
    seed : int
        Seed (>= 0) of ``numpy.random.SeedSequence``.

    Returns
    -------
    (tuple of str, ndarray)
        The keys (columns, in the table's order) and the ``(n, k)`` values (parameters' units).

    Raises
    ------
    ArgumentError
        If a correlated truncated normal cannot be drawn within its bounds (:data:`MAX_REJECTIONS`).
    """
    keys = tuple(table)
    plan = _plan(table, correlation, nominal)
    out = np.empty((n, len(keys)))
    for i, child in enumerate(np.random.SeedSequence(seed).spawn(n)):
        out[i] = _draw_one(np.random.default_rng(child), plan, len(keys), keys)
    return keys, out


def vertex_values(table: Mapping[str, Uncertainty], nominal: Mapping[str, float], max_vertices: int,
                  seed: int) -> tuple[tuple[str, ...], np.ndarray]:
    """Corners of the box of the uncertain coefficients (:meth:`Uncertainty.box` per key).

    With ``k`` entries, all ``2^k`` corners when ``2^k <= max_vertices``, in binary order (row ``j`` takes the high
    bound of key ``i`` where bit ``k - 1 - i`` of ``j`` is set: the first key varies slowest). Otherwise
    ``max_vertices`` rows: the nominal values, the ``2k`` axis extremes (the nominal values with key ``i`` at its
    low, then its high bound, for each key in turn), and ``max_vertices - 2k - 1`` distinct corners drawn at random
    with ``numpy.random.default_rng(seed)``.

    Parameters
    ----------
    table : Mapping[str, Uncertainty]
        The vehicle's ``[uncertainty]`` entries.
    nominal : Mapping[str, float]
        Nominal values.
    max_vertices : int
        Most rows returned.
    seed : int
        Seed of the random corners (used only when not all corners fit).

    Returns
    -------
    (tuple of str, ndarray)
        The keys and the ``(m, k)`` values.

    Raises
    ------
    ArgumentError
        If not all corners fit and ``max_vertices < 2k + 1``.
    """
    keys = tuple(table)
    k = len(keys)
    lo, hi = (np.array(c, dtype=float) for c in zip(*(table[key].box(nominal[key]) for key in keys), strict=True))
    if k < 63 and 2**k <= max_vertices:
        bits = (np.arange(2**k)[:, None] >> np.arange(k - 1, -1, -1)) & 1
        return keys, np.where(bits.astype(bool), hi, lo)
    if max_vertices < 2 * k + 1:
        raise ArgumentError(f"max_vertices = {max_vertices} cannot hold the nominal point and the 2k = {2 * k} axis "
                            f"extremes of the {k} uncertain coefficients (2^{k} corners do not fit): give at least "
                            f"{2 * k + 1}")
    nom = np.array([nominal[key] for key in keys], dtype=float)
    rows = [nom]
    for i in range(k):
        for bound in (lo, hi):
            r = nom.copy()
            r[i] = bound[i]
            rows.append(r)
    rng = np.random.default_rng(seed)
    seen: set[bytes] = set()
    need = max_vertices - len(rows)
    while len(seen) < need:
        for b in rng.integers(0, 2, size=(need, k), dtype=np.uint8):
            if len(seen) < need and b.tobytes() not in seen:
                seen.add(b.tobytes())
                rows.append(np.where(b.astype(bool), hi, lo))
    return keys, np.array(rows)
