"""Dive records: a glider's own measurements in SI units, read from Slocum binary files or CSV, checked.

A :class:`DiveRecord` holds time (s), depth (m), pitch (rad) and the pumped buoyancy volume (m^3), with optional
roll, heading (rad), in-situ density (kg/m^3) and temperature (degC). It is what :func:`glidectl.fit_flight_model`
calibrates a flight model on. Records are checked when they are made: non-finite values, time that does not
increase, duplicated samples, a record with no dive, pitch that looks like degrees and a volume that looks like
cm^3 are refused with a :class:`~glidectl.RecordError` that names the field.

Slocum binary files (``.dbd``, ``.sbd``, ``.mbd``, ...) are read through ``dbdreader`` (the optional extra
``glidectl[data]``): ``m_pressure`` (bar) becomes depth by the hydrostatic relation with
:data:`RECORD_DENSITY` and :data:`RECORD_GRAVITY`, ``m_de_oil_vol`` or ``m_ballast_pumped`` (cm^3, whichever the
file logs) the buoyancy volume.
"""

from __future__ import annotations

import hashlib
import itertools
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import RecordError

__all__ = ["DEFAULT_MASK", "RECORD_DENSITY", "RECORD_GRAVITY", "DiveRecord", "MaskSettings", "example_record_path",
           "read_dive_record"]

#: Density (kg/m^3) and gravity (m/s^2) that turn a pressure record into depth, ``depth = p / (rho g)``: the
#: constants of gliderflight's depth rate (``compute_dhdt``), so that both read the same depth from a file.
RECORD_DENSITY = 1025.0
RECORD_GRAVITY = 9.81

#: Smallest depth range (m) a record must span to hold a dive, and the depth a dive starts at.
MIN_DIVE_DEPTH = 5.0
#: Depth (m) shallower than which the glider is at the surface (between dives).
SURFACE_DEPTH = 2.0
#: Largest pitch magnitude (rad) accepted: more than pi/2 means the pitch was logged in degrees.
PITCH_MAX = np.pi / 2
#: Largest pumped volume magnitude (m^3) accepted: 5 litres; more means the volume was logged in cm^3.
VOLUME_MAX = 5e-3

_OPTIONAL = ("roll", "heading", "density", "temperature")
#: Optional record fields and the Slocum sensors they are read from (the first one a file logs).
_SLOCUM_OPTIONAL = (("roll", "m_roll"), ("heading", "m_heading"), ("temperature", "m_water_temp"))


@dataclass(frozen=True)
class MaskSettings:
    """Which samples a flight-model fit uses: the default mask of :meth:`DiveRecord.mask`.

    Attributes
    ----------
    surface_depth : float
        Samples shallower than this (m) are left out: surfacing, the first dive metres, wave motion.
    inflection_margin : float
        Samples within this height (m) of the depth of an inflection (where the pitch changes sign: the bottom of a
        dive, the top of a yo) are left out: the pump works and the glider pitches over there, far from a steady
        glide.
    min_pitch : float
        Samples with ``|pitch|`` below this (rad) are left out: near-level flight has no steady glide of the
        efficient branch and its angle of attack is ill-conditioned.
    """

    surface_depth: float = 20.0
    inflection_margin: float = 20.0
    min_pitch: float = np.radians(10.0)


#: The mask a fit uses unless told otherwise.
DEFAULT_MASK = MaskSettings()


def _finite_array(name: str, value: Any, n: int | None) -> np.ndarray:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise RecordError(f"dive record field '{name}' must be an array of numbers: {exc}") from None
    if a.ndim != 1:
        raise RecordError(f"dive record field '{name}' must be one-dimensional, got shape {a.shape}")
    if n is not None and a.size != n:
        raise RecordError(f"dive record field '{name}' has {a.size} samples, 'time' has {n}")
    bad = ~np.isfinite(a)
    if bad.any():
        i = int(np.argmax(bad))
        raise RecordError(f"dive record field '{name}' has {int(bad.sum())} non-finite value(s) (NaN or inf), the "
                          f"first at sample {i}; drop or fill those samples first")
    a = a.copy()
    a.setflags(write=False)
    return a


def _check_time(t: np.ndarray) -> None:
    dt = np.diff(t)
    if (dt == 0).any():
        i = int(np.argmax(dt == 0))
        raise RecordError(f"dive record field 'time' has {int((dt == 0).sum())} duplicated sample(s), the first at "
                          f"t = {t[i]:g} s (samples {i} and {i + 1}); remove duplicates first")
    if (dt < 0).any():
        i = int(np.argmax(dt < 0))
        raise RecordError(f"dive record field 'time' must increase: t[{i + 1}] = {t[i + 1]:g} s follows "
                          f"t[{i}] = {t[i]:g} s; sort the record first")


def _check_units(depth: np.ndarray, pitch: np.ndarray, volume: np.ndarray) -> None:
    span = float(depth.max() - depth.min())
    if span < MIN_DIVE_DEPTH:
        raise RecordError(f"dive record field 'depth' spans {span:.3g} m: a record with no dive (at least "
                          f"{MIN_DIVE_DEPTH:g} m are needed)")
    if np.abs(pitch).max() > PITCH_MAX:
        raise RecordError(f"dive record field 'pitch' reaches {np.abs(pitch).max():.4g}, more than pi/2: it looks "
                          "like degrees; give it in rad (np.radians)")
    if np.abs(volume).max() > VOLUME_MAX:
        raise RecordError(f"dive record field 'buoyancy_volume' reaches {np.abs(volume).max():.4g} m^3, more than "
                          f"{VOLUME_MAX * 1e3:g} litres: it looks like cm^3; give it in m^3 (cm^3 * 1e-6)")


@dataclass(frozen=True)
class DiveRecord:
    """A glider's dive record in SI units (make one with :meth:`from_arrays` or :func:`read_dive_record`).

    Attributes
    ----------
    time : ndarray
        Time (s), strictly increasing.
    depth : ndarray
        Depth (m, positive down).
    pitch : ndarray
        Pitch angle (rad, nose up positive).
    buoyancy_volume : ndarray
        Volume pumped into the external bladder (m^3; negative: the glider is made heavy).
    roll, heading : ndarray or None
        Roll and heading (rad), where recorded.
    density : ndarray or None
        In-situ density (kg/m^3), where recorded; fits use the vehicle's density otherwise.
    temperature : ndarray or None
        Water temperature (degC), where recorded (hull thermal expansion).
    source : str
        Where the record came from (a file path or ``"arrays"``).
    """

    time: np.ndarray
    depth: np.ndarray
    pitch: np.ndarray
    buoyancy_volume: np.ndarray
    roll: np.ndarray | None = None
    heading: np.ndarray | None = None
    density: np.ndarray | None = None
    temperature: np.ndarray | None = None
    source: str = field(default="arrays")

    def __post_init__(self) -> None:
        t = _finite_array("time", self.time, None)
        if t.size < 3:
            raise RecordError(f"a dive record needs at least 3 samples, got {t.size}")
        _check_time(t)
        object.__setattr__(self, "time", t)
        for name in ("depth", "pitch", "buoyancy_volume"):
            object.__setattr__(self, name, _finite_array(name, getattr(self, name), t.size))
        for name in _OPTIONAL:
            if getattr(self, name) is not None:
                object.__setattr__(self, name, _finite_array(name, getattr(self, name), t.size))
        if self.density is not None and not (self.density > 0).all():
            raise RecordError("dive record field 'density' must be positive (kg/m^3)")
        if not isinstance(self.source, str):
            raise RecordError(f"dive record 'source' must be a str, got {type(self.source).__name__}")
        _check_units(self.depth, self.pitch, self.buoyancy_volume)

    @classmethod
    def from_arrays(cls, time: Any, depth: Any, pitch: Any, buoyancy_volume: Any, *, roll: Any = None,
                    heading: Any = None, density: Any = None, temperature: Any = None,
                    source: str = "arrays") -> DiveRecord:
        """A checked record from arrays in SI units.

        Parameters
        ----------
        time : array_like
            Time (s), strictly increasing.
        depth : array_like
            Depth (m).
        pitch : array_like
            Pitch (rad).
        buoyancy_volume : array_like
            Pumped volume (m^3).
        roll, heading, density, temperature : array_like, optional
            Roll, heading (rad), in-situ density (kg/m^3), temperature (degC).
        source : str, optional
            Where the data came from (kept as the record's provenance text).

        Returns
        -------
        DiveRecord

        Raises
        ------
        RecordError
            Non-finite values, fields of different lengths, time not increasing, duplicated samples, a record
            with no dive, pitch that looks like degrees, a volume that looks like cm^3 (each names the field).
        """
        return cls(time, depth, pitch, buoyancy_volume, roll, heading, density, temperature, source)

    def __len__(self) -> int:
        return int(self.time.size)

    @property
    def provenance(self) -> str:
        """SHA-256 (first 16 hex digits) of the record's arrays: two records with the same data share it."""
        h = hashlib.sha256()
        for name in ("time", "depth", "pitch", "buoyancy_volume", *_OPTIONAL):
            a = getattr(self, name)
            h.update(name.encode() + (b"-" if a is None else np.ascontiguousarray(a).tobytes()))
        return h.hexdigest()[:16]

    @property
    def pressure(self) -> np.ndarray:
        """Gauge pressure (Pa) of the recorded depth, ``depth rho g`` with :data:`RECORD_DENSITY` and
        :data:`RECORD_GRAVITY`: a Slocum file's ``m_pressure`` again (in Pa, not bar)."""
        return self.depth * (RECORD_DENSITY * RECORD_GRAVITY)

    @property
    def vertical_speed(self) -> np.ndarray:
        """Measured vertical speed (m/s, positive up): ``-d(depth)/dt`` by central differences (one-sided at the
        ends), as gliderflight's ``compute_dhdt``."""
        return -np.gradient(self.depth) / np.gradient(self.time)

    @property
    def dive_number(self) -> np.ndarray:
        """Number of the dive each sample belongs to (0, 1, ...): a dive starts where the glider passes
        :data:`MIN_DIVE_DEPTH` going down after it was at the surface (shallower than :data:`SURFACE_DEPTH`), so
        waves about the threshold do not start new dives; samples before the first dive belong to dive 0, and a
        record that starts under water counts the dive under way as dive 0."""
        deep = self.depth > MIN_DIVE_DEPTH
        starts = np.flatnonzero(np.diff(deep.astype(np.int8)) > 0) + 1  # passes of MIN_DIVE_DEPTH going down
        surface = np.flatnonzero(self.depth < SURFACE_DEPTH)
        if self.depth[0] >= SURFACE_DEPTH and (starts.size == 0 or starts[0] != 0):
            starts = np.concatenate(([0], starts))  # a record that starts under water: its first dive is under way
        number = np.zeros(len(self), dtype=int)
        count = 0
        for prev, i in itertools.pairwise(starts):  # a few per dive: the crossings, not the samples
            k = np.searchsorted(surface, prev, side="right")
            if k < surface.size and surface[k] < i:  # surfaced since the previous pass: a new dive
                count += 1
                number[i:] = count
        return number

    def mask(self, settings: MaskSettings = DEFAULT_MASK) -> np.ndarray:
        """The samples a flight-model fit uses (True: used).

        Leaves out the surface layer, the samples within a height of the inflections before and after them
        (:meth:`inflections`: pumping and pitching over) and shallow pitch (:class:`MaskSettings`).

        Parameters
        ----------
        settings : MaskSettings, optional
            The depths and pitch limit; default :data:`DEFAULT_MASK`.

        Returns
        -------
        ndarray of bool

        Raises
        ------
        RecordError
            If ``settings`` is not a :class:`MaskSettings`.
        """
        if not isinstance(settings, MaskSettings):
            raise RecordError(f"settings must be a MaskSettings, got {type(settings).__name__}")
        turns = self.inflections(settings.min_pitch)
        near = np.zeros(len(self), dtype=bool)
        if turns.size:
            d = self.depth[turns]
            k = np.searchsorted(turns, np.arange(len(self)), side="right")  # inflections at or before each sample
            before = np.where(k > 0, d[np.maximum(k - 1, 0)], np.nan)
            after = np.where(k < turns.size, d[np.minimum(k, turns.size - 1)], np.nan)
            with np.errstate(invalid="ignore"):
                near = ((np.abs(self.depth - before) < settings.inflection_margin)
                        | (np.abs(self.depth - after) < settings.inflection_margin))
        return (self.depth >= settings.surface_depth) & ~near & (np.abs(self.pitch) >= settings.min_pitch)

    def inflections(self, min_pitch: float = DEFAULT_MASK.min_pitch) -> np.ndarray:
        """Indices of the samples where the glider pitches over: the sign of the pitch changes (nose down to nose
        up at the bottom of a dive or yo, nose up to nose down at its top), near-level samples (``|pitch| <
        min_pitch``) taking the sign before them.

        Parameters
        ----------
        min_pitch : float, optional
            Pitch magnitude (rad) below which a sample does not change the sign.

        Returns
        -------
        ndarray of int
            The first sample of each new sign.
        """
        sign = np.where(np.abs(self.pitch) >= min_pitch, np.sign(self.pitch), 0.0)
        held = np.flatnonzero(sign)
        if held.size == 0:
            return np.zeros(0, dtype=int)
        last = np.maximum.accumulate(np.where(sign != 0, np.arange(len(self)), held[0]))
        sign = sign[last]  # near-level samples keep the sign before them (the first sign before any)
        return np.flatnonzero(np.diff(sign) != 0) + 1

    def plot(self, ax: Any = None) -> Any:
        """Depth, pitch and pumped volume against time, the samples of the default fit mask marked.

        Parameters
        ----------
        ax : three Axes, optional
            Where to draw; a new figure otherwise.

        Returns
        -------
        ndarray of Axes
        """
        from .plotting import plot_dive_record

        return plot_dive_record(self, ax)


def _require_dbdreader() -> Any:
    try:
        import dbdreader
    except ImportError:
        raise RecordError("reading Slocum binary files needs the optional package dbdreader: "
                          "pip install 'glidectl[data]'") from None
    return dbdreader


def _read_slocum(path: Path, cache_dir: str | None) -> DiveRecord:
    dbdreader = _require_dbdreader()
    kwargs = {} if cache_dir is None else {"cacheDir": str(cache_dir)}
    try:
        dbd = dbdreader.DBD(str(path), **kwargs)
    except Exception as exc:  # dbdreader raises its own error types for unreadable files and missing cache files
        raise RecordError(f"cannot read Slocum file '{path}': {exc}") from None
    try:
        listed = dbd.parameterNames  # a list (DBD) or a dict of lists by 'eng' and 'sci' (MultiDBD)
        names = set(listed) if isinstance(listed, list) else {n for v in listed.values() for n in v}
        volume_name = next((n for n in ("m_de_oil_vol", "m_ballast_pumped")
                            if n in names and dbd.get(n)[0].size > 2), None)
        missing = [n for n in ("m_pressure", "m_pitch") if n not in names]
        if volume_name is None:
            missing.append("m_de_oil_vol or m_ballast_pumped")
        if missing:
            raise RecordError(f"Slocum file '{path}' does not log {', '.join(missing)}")
        extra = {field: n for field, n in _SLOCUM_OPTIONAL if n in names and dbd.get(n)[0].size > 2}
        arrays = dbd.get_sync("m_pressure", "m_pitch", volume_name, *extra.values())
    finally:
        dbd.close()
    t, pressure, pitch, volume = arrays[:4]
    keep = np.isfinite(t) & np.isfinite(pressure) & np.isfinite(pitch) & np.isfinite(volume)
    t, order = np.unique(t[keep], return_index=True)  # sorted, duplicated time stamps dropped
    pick = np.flatnonzero(keep)[order]
    depth = pressure[pick] * 1e5 / (RECORD_DENSITY * RECORD_GRAVITY)
    # optional fields (interpolated onto the pressure's time base) only where they cover every sample kept
    opt = {k: a[pick] for k, a in zip(extra, arrays[4:], strict=True) if np.all(np.isfinite(a[pick]))}
    return DiveRecord(t, depth, pitch[pick], volume[pick] * 1e-6, **opt, source=str(path))


def example_record_path(name: str = "ammonite-2008-028-01-000.mbd") -> Path:
    """Path of a real Slocum record shipped in the ``dbdreader`` wheel (the optional extra ``glidectl[data]``).

    The default is a 107-minute dive of the deep Slocum glider 'ammonite' to 608 m (2008), with ``m_pressure``,
    ``m_pitch``, ``m_de_oil_vol``, ``m_roll`` and ``m_heading``: the record glidectl's flight-fit design and tests
    calibrate on.

    Parameters
    ----------
    name : str, optional
        File name in ``dbdreader``'s ``data`` folder.

    Returns
    -------
    Path

    Raises
    ------
    RecordError
        Without ``dbdreader``, or when its wheel has no such file.
    """
    p = Path(_require_dbdreader().__file__).parent / "data" / name
    if not p.is_file():
        raise RecordError(f"dbdreader ships no record named {name!r} (looked in {p.parent})")
    return p


def _read_csv(path: Path) -> DiveRecord:
    try:
        data = np.genfromtxt(path, delimiter=",", names=True, dtype=float, encoding="utf-8-sig")  # Excel's BOM too
    except (OSError, ValueError) as exc:
        raise RecordError(f"cannot read CSV dive record '{path}': {exc}") from None
    names = data.dtype.names or ()
    missing = [n for n in ("time", "depth", "pitch", "buoyancy_volume") if n not in names]
    if missing:
        raise RecordError(f"CSV dive record '{path}' has no column(s) {', '.join(missing)}; its header must name "
                          "time, depth, pitch, buoyancy_volume (SI units) and optionally " + ", ".join(_OPTIONAL))
    cols = {n: np.atleast_1d(data[n]) for n in names if n in ("time", "depth", "pitch", "buoyancy_volume",
                                                                 *_OPTIONAL)}
    return DiveRecord(**cols, source=str(path))


def read_dive_record(path: str | Path, cache_dir: str | Path | None = None) -> DiveRecord:
    """Read a dive record from a Slocum binary file (through ``dbdreader``) or a CSV file in SI units.

    Parameters
    ----------
    path : str or Path
        A Slocum binary file (``.dbd``, ``.sbd``, ``.mbd``, ``.ebd``, ...; compressed ``.dcd`` etc. too) or a
        ``.csv`` file whose header names ``time, depth, pitch, buoyancy_volume`` (s, m, rad, m^3) and optionally
        ``roll, heading, density, temperature``.
    cache_dir : str or Path, optional
        Where ``dbdreader`` keeps (and writes) the sensor-list cache files (``.cac``) of Slocum files; default
        ``dbdreader``'s own.

    Returns
    -------
    DiveRecord
        For Slocum files: ``m_pressure`` (bar) to depth with :data:`RECORD_DENSITY`, :data:`RECORD_GRAVITY`;
        ``m_pitch``, ``m_roll``, ``m_heading`` (rad); ``m_de_oil_vol`` or ``m_ballast_pumped`` (cm^3) to m^3;
        ``m_water_temp`` (degC) as the temperature; all on the time base of ``m_pressure`` (dbdreader's
        ``get_sync``, linear interpolation). Samples without pressure, pitch or volume are dropped; an optional
        field that does not cover every remaining sample is left out.

    Raises
    ------
    RecordError
        A file that does not exist or cannot be read, misses a field, or whose data fail the record's checks;
        a Slocum file without the optional ``dbdreader`` installed.
    """
    p = Path(path)
    if not p.is_file():
        raise RecordError(f"no dive record file '{p}'")
    if p.suffix.lower() == ".csv":
        return _read_csv(p)
    return _read_slocum(p, None if cache_dir is None else str(cache_dir))
