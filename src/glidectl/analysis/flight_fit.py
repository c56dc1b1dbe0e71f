"""Calibrate a flight model to a glider's own dive record: :func:`fit_flight_model`.

The model is the steady-state glide of :func:`glidectl.steady_flight` at the recorded pitch and the net heaviness
of :func:`glidectl.excess_mass` (hull volume, compressibility, thermal expansion, pumped volume, density), with the
vehicle's lift and drag law (:func:`glidectl.hydro.lift_drag`). The coefficients named in ``fit`` minimise the
squared difference between modelled and measured vertical speed over the masked samples (scipy's
``least_squares``, trust-region reflective, within each coefficient's sign constraint, from the start values with
the hull volume near neutral buoyancy); the field calibrates
``volume`` and the parasitic drag (gliderflight's ``Vg`` and ``Cd0``; the Seaglider basestation's ``hd_b``), the
default here. Standard errors come from the Jacobian at the optimum, ``s^2 (J^T J)^-1``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from scipy.optimize import least_squares

from .. import checks
from ..errors import ArgumentError, OutputError, RecordError, SolverError, VehicleFileError
from ..hydro import excess_mass, gliderflight_coefficients, hull_buoyancy_keys, lift_drag
from ..params import (
    GLIDERFLIGHT_DEFAULTS,
    HULL_MASS_RATIO,
    HYDRO_SPECS,
    PARAMETER_SPECS,
    THESIS_LIFT_DRAG_KEYS,
    Vehicle,
)
from ..records import DEFAULT_MASK, DiveRecord, MaskSettings
from ..trim.flight import SteadyFlight, steady_flight

__all__ = ["DEFAULT_FIT", "MATCH_SPEED", "SEAGLIDER_LENGTH", "FlightFit", "fit_flight_model", "law_start",
           "predict_flight"]

#: The coefficients fitted when ``fit`` is not given: hull volume and the law's parasitic drag.
DEFAULT_FIT = {"thesis": ("volume", "K_D0"), "seaglider": ("volume", "hd_b"), "gliderflight": ("volume", "Cd0")}
#: Speed (m/s) at which a law's starting coefficients are matched to the vehicle's current law (:func:`law_start`).
MATCH_SPEED = 0.25
#: Hull length (m) of the Seaglider law where the vehicle gives none: the Seaglider's (Eriksen et al. 2001).
SEAGLIDER_LENGTH = 1.8
#: Typical magnitudes of coefficients whose start value is 0 (the scale of the fit's unknowns).
_TYPICAL = {"compressibility": 5e-10, "thermal_expansion": 7e-5, "K_L0": 1.0, "Cd1": 10.0, "ah": 1.0, "aw": 1.0,
            "hd_c": 1e-5}
#: Smallest ratio of the Jacobian's singular values accepted (central differences: errors near 1e-10).
_SINGULAR_RCOND = 1e-7
_VOLUME_SCAN = 9  # volumes scanned for the fit's start, within the pump's reach of the neutral estimate
_CENTRAL_STEP = np.finfo(float).eps ** (1 / 3)
_CORRELATION_MIN = 0.05  # smallest |correlation| between fitted coefficients FlightFit.to_toml writes


def _match_data(veh: Vehicle) -> tuple[float, float, float]:
    """Lift slope (N s^2/m^2/rad), drag at zero incidence and its alpha^2 factor (N s^2/m^2) of the vehicle's law
    at :data:`MATCH_SPEED`, per unit V^2."""
    V2, a = MATCH_SPEED**2, 0.05
    lift, _ = lift_drag(veh, 1.0, a)
    lift0, d0 = lift_drag(veh, V2, 0.0)
    _, d1 = lift_drag(veh, V2, 2 * a)
    return float(lift - lift0 / V2) / a, float(d0) / V2, float(d1 - d0) / (V2 * 4 * a * a)


def law_start(veh: Vehicle, law: str) -> Vehicle:
    """The vehicle with another lift and drag law whose coefficients match its current law at :data:`MATCH_SPEED`.

    The lift slope, the zero-incidence drag and the drag's ``alpha^2`` factor at ``V = MATCH_SPEED`` are carried
    over; a Seaglider law takes the vehicle's ``length`` or :data:`SEAGLIDER_LENGTH`, a gliderflight law
    gliderflight's wing defaults (:data:`~glidectl.params.GLIDERFLIGHT_DEFAULTS`) with ``Cd0``, ``Cd1`` and the
    wing lift slope ``aw`` set by the match (and ``ah`` lowered where the matched slope is below it). This is
    where a fit with a named law starts.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider.
    law : str
        ``"thesis"``, ``"seaglider"`` or ``"gliderflight"``.

    Returns
    -------
    Vehicle

    Raises
    ------
    VehicleFileError
        If ``law`` is unknown.
    """
    if not isinstance(law, str) or law not in HYDRO_SPECS:
        raise VehicleFileError(f"law_start: unknown hydrodynamic law {law!r}; known: {', '.join(HYDRO_SPECS)}")
    if law == veh.law:
        return veh
    slope, d0, d2 = _match_data(veh)
    rho = veh.density
    src = f"matched to the '{veh.law}' law at {MATCH_SPEED} m/s (glidectl.law_start)"
    if law == "thesis":
        return veh.with_hydrodynamics("thesis", source=src, K_L0=0.0, K_L=slope, K_D0=d0, K_D=d2)
    if law == "seaglider":
        length = veh.params.get("length", SEAGLIDER_LENGTH)
        deg = 180.0 / np.pi
        q = 0.5 * rho * MATCH_SPEED**2
        return veh.with_hydrodynamics("seaglider", source=src, length=length,
                                      hd_a=slope / (0.5 * rho * length**2 * deg),
                                      hd_b=d0 * MATCH_SPEED**2 / (q**0.75 * length**2),
                                      hd_c=d2 / (deg**2 * 0.5 * rho * length**2))
    # law == "gliderflight"
    gf = {k: veh.params.get(k, v) for k, v in GLIDERFLIGHT_DEFAULTS.items()}
    half_rho_s = 0.5 * rho * gf["S"]
    total = slope / half_rho_s  # ah + aw; the hull keeps gliderflight's ah where the total allows it
    gf["ah"] = min(gf["ah"], total)
    return veh.with_hydrodynamics("gliderflight", source=src, Cd0=d0 / half_rho_s, Cd1=d2 / half_rho_s,
                                  aw=total - gf["ah"], **gf)


@dataclass(frozen=True)
class FlightFit:
    """A flight model calibrated to a dive record (:func:`fit_flight_model`).

    Attributes
    ----------
    vehicle : Vehicle
        The vehicle with the fitted values; their source names the record.
    start : Vehicle
        The vehicle the fit started from (the law's starting coefficients).
    params : dict
        Fitted value of each coefficient (units of the vehicle file).
    stderr : dict
        Standard error of each coefficient, ``sqrt(diag(s^2 (J^T J)^-1))`` with ``s^2`` the residual variance.
    rms : float
        Root mean square of the vertical-speed residual over the samples used (m/s).
    residual : ndarray
        Modelled minus measured vertical speed at the samples used (m/s).
    used : ndarray of bool
        The samples of the record the fit used (the mask).
    cv_rms : float or None
        Cross-validated RMS (m/s): each of ``holdout`` blocks of the used samples (whole dives where the record has
        that many, else contiguous blocks in time) predicted by the fit to the others; None without ``holdout``.
    cv_fold_rms : tuple of float
        RMS of each held-out block (m/s).
    correlation : ndarray
        Correlation matrix of the fitted coefficients.
    record : DiveRecord
        The record fitted.
    context : dict
        Solver details: ``nfev``, ``status``, ``message``, ``cost``, ``n_used``, ``law``, ``holdout_blocks``
        (``"dives"``, ``"time blocks"``, or ``""`` without cross-validation).
    """

    vehicle: Vehicle = field(repr=False, compare=False)
    start: Vehicle = field(repr=False, compare=False)
    params: dict[str, float]
    stderr: dict[str, float]
    rms: float
    residual: np.ndarray = field(repr=False)
    used: np.ndarray = field(repr=False)
    cv_rms: float | None
    cv_fold_rms: tuple[float, ...]
    correlation: np.ndarray = field(repr=False)
    record: DiveRecord = field(repr=False, compare=False)
    context: dict[str, Any] = field(repr=False, compare=False)

    @property
    def provenance(self) -> str:
        """The fitted vehicle's parameter hash."""
        return self.vehicle.provenance

    @property
    def law(self) -> str:
        """The lift and drag law fitted."""
        return self.vehicle.law

    def predict(self, record: DiveRecord | None = None) -> SteadyFlight:
        """Steady-state flight of the fitted vehicle at every sample of ``record`` (default the fitted record).

        Parameters
        ----------
        record : DiveRecord, optional

        Returns
        -------
        SteadyFlight
            ``speed``, ``alpha``, ``vertical_speed``, ``horizontal_speed`` at every sample.

        Raises
        ------
        RecordError
            If ``record`` is not a DiveRecord.
        """
        return predict_flight(self.vehicle, self.record if record is None else record)

    def summary(self) -> str:
        """The fitted coefficients with standard errors, and the RMS values."""
        rows = [f"{self.law} law fitted to {self.record.source} ({self.context['n_used']} samples)"]
        rows += [f"  {k} = {v:.6g} +- {self.stderr[k]:.2g}" for k, v in self.params.items()]
        cv = "" if self.cv_rms is None else f", cross-validated {self.cv_rms:.4f} m/s"
        rows.append(f"  RMS vertical speed {self.rms:.4f} m/s{cv}")
        return "\n".join(rows)

    def to_toml(self, path: str | Path) -> Path:
        """Write the fitted vehicle as a complete vehicle file (:meth:`glidectl.Vehicle.to_toml`), with the fit's
        standard errors in its ``[uncertainty]`` table.

        Each fitted coefficient gets a normal entry, ``std`` its standard error and source "standard error of the
        fit to <record>", and each pair of fitted coefficients whose correlation exceeds 0.05 in magnitude a
        correlation (every pair where leaving the small ones out would make the correlation matrix indefinite). The
        fitted vehicle's other entries are kept.

        Parameters
        ----------
        path : str or Path

        Returns
        -------
        Path

        Raises
        ------
        OutputError
            If the file cannot be written.
        """
        p = Path(path)
        try:
            p.write_text(self.uncertain_vehicle().to_toml(), encoding="utf-8")
        except OSError as exc:
            raise OutputError(f"cannot write vehicle file '{p}': {exc.strerror or exc}") from None
        return p

    def uncertain_vehicle(self) -> Vehicle:
        """The fitted vehicle with the fit's standard errors (and correlations beyond 0.05) as normal entries of its
        ``[uncertainty]`` table: what :meth:`to_toml` writes, and what :meth:`glidectl.Vehicle.sample` draws the
        coefficients the fit does not pin down from (a Monte Carlo study of the fitted glider).

        Returns
        -------
        Vehicle

        Raises
        ------
        VehicleFileError
            If the standard errors cannot form a valid table (not expected from a fit that succeeded).
        """
        veh = self.vehicle
        names = list(self.params)
        source = f"standard error of the fit to {self.record.source}"
        fitted = {k: {"std": s, "source": source} for k, s in self.stderr.items() if np.isfinite(s) and s > 0}
        table: dict[str, Any] = {**{k: u for k, u in veh.uncertainty.items() if k not in fitted}, **fitted}
        kept = {pair: rho for pair, rho in veh.correlation if not set(pair) & set(fitted)}
        pairs = {(a, b): float(np.clip(self.correlation[i, j], -1.0, 1.0)) for i, a in enumerate(names)
                 for j, b in enumerate(names) if i < j and a in fitted and b in fitted}
        large = {p: r for p, r in pairs.items() if abs(r) > _CORRELATION_MIN}
        try:
            return veh.with_uncertainty(table, {**kept, **large})
        except VehicleFileError:  # leaving out the small correlations broke positive semidefiniteness: write all
            return veh.with_uncertainty(table, {**kept, **pairs})

    def plot(self, ax: Any = None) -> Any:
        """Measured against modelled vertical speed over the record, and the residual against depth.

        Parameters
        ----------
        ax : two Axes, optional
            Where to draw; a new figure otherwise.

        Returns
        -------
        ndarray of Axes
        """
        from ..plotting import plot_flight_fit

        return plot_flight_fit(self, ax)


def _record(record: Any) -> DiveRecord:
    if not isinstance(record, DiveRecord):
        raise RecordError(f"record must be a glidectl DiveRecord (gc.read_dive_record or "
                          f"gc.DiveRecord.from_arrays), got {type(record).__name__}")
    return record


def predict_flight(veh: Vehicle, record: DiveRecord, used: np.ndarray | None = None) -> SteadyFlight:
    """Steady-state flight of ``veh`` at the samples ``used`` (default all) of ``record``: the flight model a fit
    calibrates, at the recorded pitch, depth, pumped volume, density and temperature.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider (any law; its hull needs ``mass`` and ``volume``, :func:`glidectl.excess_mass`).
    record : DiveRecord
        The record.
    used : ndarray of bool, optional
        The samples to solve (default all).

    Returns
    -------
    SteadyFlight
        Speed, angle of attack, vertical and horizontal speed at each sample solved.

    Raises
    ------
    RecordError
        If ``record`` is not a DiveRecord.
    ModelError
        If the hull's mass or volume is unknown.
    """
    record = _record(record)
    sel = slice(None) if used is None else used
    if record.density is not None:
        rho = record.density[sel]
    else:  # the vehicle's density profile at the recorded depths, or its constant density (None)
        rho = veh.water_density(record.depth[sel]) if veh.density_profile else None
    temp = None if record.temperature is None else record.temperature[sel]
    m0 = excess_mass(veh, record.depth[sel], record.buoyancy_volume[sel], density=rho, temperature=temp,
                     pressure=record.pressure[sel])
    return steady_flight(veh, record.pitch[sel], m0, density=rho)


def _mask(record: DiveRecord, mask: Any) -> np.ndarray:
    if mask is None or isinstance(mask, MaskSettings):
        return record.mask(mask or DEFAULT_MASK)
    m = np.asarray(mask)
    if m.dtype != bool or m.shape != (len(record),):
        raise RecordError(f"mask must be a MaskSettings or a boolean array of the record's {len(record)} samples, "
                          f"got {m.dtype} of shape {m.shape}")
    return m


def _names(start: Vehicle, fit: Any) -> tuple[str, ...]:
    names = DEFAULT_FIT[start.law] if fit is None else ((fit,) if isinstance(fit, str) else tuple(fit))
    spec = dict(HYDRO_SPECS[start.law])
    if start.law == "thesis":
        spec.update({k: None for k in THESIS_LIFT_DRAG_KEYS})
    if not names:
        raise ArgumentError("fit must name at least one coefficient")
    for n in names:
        if n not in spec:
            raise ArgumentError(f"fit: {n!r} is not a coefficient of the '{start.law}' law or the hull; fittable: "
                                f"{', '.join(spec)}")
    if len(set(names)) != len(names):
        raise ArgumentError(f"fit names a coefficient twice: {names}")
    return names


def _coefficient_values(start: Vehicle, names: Sequence[str]) -> np.ndarray:
    """Start values: the vehicle's, the hull defaults, or gliderflight's derived ``aw`` and ``Cd1``."""
    values = dict(hull_buoyancy_keys(start))
    if start.law == "gliderflight":
        slope, _, cd1 = gliderflight_coefficients(start)
        values.update(aw=slope - start.params["ah"], Cd1=cd1)
    return np.array([start.params.get(n, values.get(n, 0.0)) for n in names], dtype=float)


def _bounds(start: Vehicle, names: Sequence[str], scale: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of the scaled unknowns: each coefficient's sign constraint, and for the hull's ``volume`` and
    ``mass`` the plausible ratio of displaced water to mass (:data:`~glidectl.params.HULL_MASS_RATIO`)."""
    spec = {**PARAMETER_SPECS["underwater_glider"], **HYDRO_SPECS[start.law]}
    lo = np.array([0.0 if spec[n].constraint in ("positive", "nonnegative") else -np.inf for n in names])
    hi = np.full(len(names), np.inf)
    hull = hull_buoyancy_keys(start)
    r_lo, r_hi = HULL_MASS_RATIO
    rho = hull["density"]
    for i, n in enumerate(names):
        if n == "volume":
            lo[i], hi[i] = r_lo * hull["mass"] / rho, r_hi * hull["mass"] / rho
        elif n == "mass":
            lo[i], hi[i] = rho * hull["volume"] / r_hi, rho * hull["volume"] / r_lo
    return lo / scale, hi / scale


class _Problem:
    """The least-squares problem of one fit: the residual of the scaled coefficients ``x`` (value / scale)."""

    def __init__(self, start: Vehicle, record: DiveRecord, names: Sequence[str], used: np.ndarray,
                 source: str) -> None:
        self.start, self.names, self.source = start, tuple(names), source
        self.record, self.used = record, used

    def vehicle(self, values: np.ndarray) -> Vehicle:
        return self.start.with_hydrodynamics(source=self.source,
                                             **{n: float(v) for n, v in zip(self.names, values, strict=True)})

    def residual(self, values: np.ndarray, used: np.ndarray | None = None) -> np.ndarray:
        sel = self.used if used is None else used
        flight = predict_flight(self.vehicle(values), self.record, sel)
        return flight.vertical_speed - self.record.vertical_speed[sel]


def _solve(problem: _Problem, x0_values: np.ndarray, scale: np.ndarray, used: np.ndarray) -> Any:
    lo, hi = _bounds(problem.start, problem.names, scale)
    inside = (np.where(np.isfinite(lo), lo + 1e-12, lo), np.where(np.isfinite(hi), hi - 1e-12, hi))
    x0 = np.clip(x0_values / scale, *inside)
    res = least_squares(lambda x: problem.residual(x * scale, used), x0, bounds=(lo, hi), method="trf",
                        x_scale=1.0, xtol=1e-10, ftol=1e-10, gtol=1e-10, max_nfev=200)
    if res.status <= 0 or not np.all(np.isfinite(res.x)):
        raise SolverError(f"the flight-model fit of {', '.join(problem.names)} did not converge "
                          f"({res.message}); start from values nearer the vehicle's, or fit fewer coefficients")
    return res


def _central_jacobian(problem: _Problem, x: np.ndarray, scale: np.ndarray, used: np.ndarray,
                      bounds: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """The residual's Jacobian in the scaled unknowns by central differences (step ``eps^(1/3)`` relative): errors
    near 1e-10, so that coefficients the record cannot tell apart show as a singular Jacobian. A coefficient within
    a step of a bound gets the second-order one-sided difference away from it (no step leaves the bounds)."""
    lower, upper = bounds
    J = np.empty((int(used.sum()), x.size))
    f0 = problem.residual(x * scale, used)
    for k in range(x.size):
        h = _CENTRAL_STEP * max(abs(x[k]), 1.0)
        step = np.zeros(x.size)
        step[k] = h
        if x[k] - h >= lower[k] and x[k] + h <= upper[k]:
            up, down = problem.residual((x + step) * scale, used), problem.residual((x - step) * scale, used)
            J[:, k] = (up - down) / (2 * h)
        else:
            d = 1.0 if x[k] - h < lower[k] else -1.0  # step away from the bound
            J[:, k] = d * (-3 * f0 + 4 * problem.residual((x + d * step) * scale, used)
                           - problem.residual((x + 2 * d * step) * scale, used)) / (2 * h)
    return J


def _covariance(problem: _Problem, res: Any, scale: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Standard errors and correlation from the Jacobian; SolverError naming what cannot be told apart."""
    J = _central_jacobian(problem, res.x, scale, problem.used, _bounds(problem.start, problem.names, scale))
    _, sv, vt = np.linalg.svd(J, full_matrices=False)
    if sv[-1] <= _SINGULAR_RCOND * sv[0]:
        null = np.abs(vt[-1])
        involved = [problem.names[i] for i in np.flatnonzero(null > 0.1 * null.max())]
        raise SolverError(f"the dive record cannot tell apart {', '.join(involved)}: the fit's Jacobian is singular "
                          f"(condition number {sv[0] / max(sv[-1], 1e-300):.2g}); fix one of them or add samples "
                          "that vary them differently (other pitch, buoyancy or depth)")
    dof = max(n - len(problem.names), 1)
    s2 = 2.0 * res.cost / dof
    cov_x = np.linalg.inv(J.T @ J) * s2
    err = np.sqrt(np.diag(cov_x))
    corr = cov_x / np.outer(err, err)
    return err * np.abs(scale), corr


def _volume_start(problem: _Problem, values: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """Start values with the hull volume, when it is fitted, near neutral buoyancy. The volume sets which samples
    have a steady glide at all: a start a kilogram or two from neutral leaves many without one, where the objective
    is flat, and the local solver can stall there. The estimate makes the median heaviness of the dives and of the
    climbs equal and opposite (a symmetric sawtooth); a scan of :data:`_VOLUME_SCAN` volumes within the pump's reach
    about it keeps the one of least squares."""
    if "volume" not in problem.names:
        return values
    i = problem.names.index("volume")
    lo, hi = (b[i] * scale[i] for b in _bounds(problem.start, problem.names, scale))
    rec, used = problem.record, problem.used
    dives, climbs = used & (rec.pitch < 0), used & (rec.pitch > 0)
    centre = values[i]
    if dives.any() and climbs.any():
        hull = {**hull_buoyancy_keys(problem.start), **dict(zip(problem.names, values, strict=True))}
        rho, eps = hull["density"], hull["compressibility"]
        dv = np.median(rec.buoyancy_volume[dives]) + np.median(rec.buoyancy_volume[climbs])
        p = np.median(rec.pressure[dives]) + np.median(rec.pressure[climbs])
        centre = (2 * hull["mass"] / rho - dv) / (2 - eps * p)
    reach = max(float(np.max(np.abs(rec.buoyancy_volume[used]))), 1e-6)
    best, out = np.inf, values.copy()
    for v in np.clip(centre + reach * np.linspace(-1.0, 1.0, _VOLUME_SCAN), lo * (1 + 1e-9), hi * (1 - 1e-9)):
        trial = values.copy()
        trial[i] = v
        r = problem.residual(trial)
        if r @ r < best:
            best, out = float(r @ r), trial
    return out


def _check_glides(problem: _Problem, values: np.ndarray) -> None:
    """SolverError when some used samples have no steady glide at the fitted values: their modelled vertical speed
    is 0, a jump in the objective, so the optimum and its standard errors mean nothing."""
    flight = predict_flight(problem.vehicle(values), problem.record, problem.used)
    bad = ~flight.feasible
    if bad.any():
        t = problem.record.time[problem.used][bad]
        raise SolverError(
            f"at the fitted {', '.join(f'{k} = {v:.6g}' for k, v in zip(problem.names, values, strict=True))}, "
            f"{int(bad.sum())} of the {bad.size} samples used have no steady glide (pitch too shallow, or of the "
            f"other sign, for their buoyancy; the first at t = {t[0] - problem.record.time[0]:.0f} s into the "
            "record): the fit's objective jumps there. Leave them out with mask=, or fit other coefficients")


def _folds(used: np.ndarray, dives: np.ndarray, k: int) -> tuple[list[np.ndarray], str]:
    """``k`` held-out blocks of the used samples and what they are: whole dives (``"dives"``) where the record has
    at least ``k`` dives with used samples, else contiguous blocks in time (``"time blocks"``)."""
    numbers = np.unique(dives[used])
    if numbers.size >= k:
        return [used & np.isin(dives, group) for group in np.array_split(numbers, k)], "dives"
    idx = np.flatnonzero(used)
    return [np.isin(np.arange(used.size), block) for block in np.array_split(idx, k)], "time blocks"


def fit_flight_model(veh: Vehicle, record: DiveRecord, law: str | None = None, fit: Sequence[str] | str | None = None,
                     mask: Any = None, holdout: int | None = None) -> FlightFit:
    """Calibrate the vehicle's flight model to a dive record.

    Fits the coefficients ``fit`` so that the steady-state vertical speed of :func:`glidectl.steady_flight` at the
    recorded pitch and net heaviness (:func:`glidectl.excess_mass`) matches the measured one (``-d depth/dt``) over
    the masked samples, in the least-squares sense.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider; its hull needs a ``mass`` and ``volume`` (given, or derived from ``m``).
    record : DiveRecord
        The dive record.
    law : str, optional
        ``None`` keeps the vehicle's law and values; ``"thesis"``, ``"seaglider"`` or ``"gliderflight"`` starts
        from that law matched to the vehicle's current law at :data:`MATCH_SPEED` (:func:`law_start`).
    fit : sequence of str, optional
        The coefficients to fit (law or hull keys); default :data:`DEFAULT_FIT`: ``volume`` and the law's
        parasitic drag (``K_D0``, ``hd_b`` or ``Cd0``).
    mask : MaskSettings or ndarray of bool, optional
        The samples used: default :meth:`DiveRecord.mask` with :data:`~glidectl.records.DEFAULT_MASK` (surface,
        inflections and shallow pitch left out).
    holdout : int, optional
        Number of held-out blocks for cross-validation (at least 2): groups of whole dives where the record has at
        least that many dives, else contiguous blocks in time; each block is predicted by the fit to the others,
        and their pooled RMS is ``cv_rms``.

    Returns
    -------
    FlightFit

    Raises
    ------
    RecordError
        ``record`` is not a DiveRecord, a bad mask, or fewer usable samples than coefficients (plus one).
    ArgumentError
        An unknown coefficient in ``fit``, a bad ``holdout``.
    SolverError
        The fit does not converge, its Jacobian is singular (the message names the coefficients the record
        cannot tell apart), or some used samples have no steady glide at the fitted values.
    VehicleFileError
        An unknown law.
    """
    record = _record(record)
    veh = checks.vehicle("veh", veh, kind="underwater_glider")
    start = veh if law is None else law_start(veh, law)
    names = _names(start, fit)
    used = _mask(record, mask)
    n = int(used.sum())
    if n <= len(names):
        raise RecordError(f"the mask leaves {n} usable sample(s) of {len(record)} for {len(names)} coefficient(s); "
                          "a fit needs more samples than coefficients (widen the mask or fit fewer)")
    if holdout is not None and (isinstance(holdout, bool) or not isinstance(holdout, int | np.integer)
                                or not 2 <= holdout <= n // (len(names) + 1)):
        raise ArgumentError(f"holdout must be a whole number of blocks from 2 to {n // (len(names) + 1)}, "
                            f"got {holdout!r}")
    source = f"fit_flight_model to {record.source} (record {record.provenance}, {n} samples)"
    problem = _Problem(start, record, names, used, source)
    values0 = _coefficient_values(start, names)
    scale = np.where(values0 != 0, np.abs(values0), [_TYPICAL.get(nm, 1.0) for nm in names])
    values0 = _volume_start(problem, values0, scale)
    res = _solve(problem, values0, scale, used)
    values = res.x * scale
    _check_glides(problem, values)
    stderr, corr = _covariance(problem, res, scale, n)
    fold_rms: list[float] = []
    blocks = ""
    if holdout:
        sq = 0.0
        folds, blocks = _folds(used, record.dive_number, int(holdout))
        for block in folds:
            r = _solve(problem, values, scale, used & ~block)
            e = problem.residual(r.x * scale, block)
            fold_rms.append(float(np.sqrt(np.mean(e * e))))
            sq += float(np.sum(e * e))
        cv = float(np.sqrt(sq / n))
    residual = res.fun.copy()
    return FlightFit(vehicle=problem.vehicle(values), start=start,
                     params={k: float(v) for k, v in zip(names, values, strict=True)},
                     stderr={k: float(v) for k, v in zip(names, stderr, strict=True)},
                     rms=float(np.sqrt(np.mean(residual**2))), residual=residual, used=used,
                     cv_rms=cv if holdout else None, cv_fold_rms=tuple(fold_rms), correlation=corr, record=record,
                     context={"nfev": int(res.nfev), "status": int(res.status), "message": str(res.message),
                              "cost": float(res.cost), "n_used": n, "law": start.law, "holdout_blocks": blocks})
