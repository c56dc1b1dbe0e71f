"""The build cache of ``glidectl report``: whole design results, and sub-results a design chooses to cache.

Everything lives under ``<out>/.cache/``:

- ``designs/<name>/<key>.pkl``: the files one build of a design wrote (``report.pdf``, the PNGs, ``numbers.json``)
  and the data files the build read. The key hashes the cache format, glidectl's version and source code, the
  design file's content, the quick flag and the repr of the settings used (the design's frozen ``QUICK`` or ``FULL``
  dataclass). The files the design read while it ran (vehicle TOML files, presets included, and any other data
  file) are recorded with their SHA-256 and checked again on every lookup, so a changed vehicle file invalidates
  exactly the designs that read it. A changed setting changes the design file, hence its key.
- ``results/<key>.pkl``: values cached by :func:`cached` inside a design, keyed by what the design passes (include
  the settings fields and the vehicle provenance the value depends on) and glidectl's version and source code, with
  the id of the build that wrote them; ``results/<key>.lock`` is the lock a process holds while it computes that
  value (another process of the build that asks for it waits, then reads it; the files stay, empty).
- ``timings.json``: the last build time of every design (quick and full), for the progress estimates and the order
  of a build (longest first); before a design's first build its declared ``EXPECTED_SECONDS`` stands in
  (:func:`expected_seconds`).

Entries are pickles tagged with :data:`CACHE_FORMAT`; an entry that cannot be read, has another tag or key, or is
truncated is ignored (and rebuilt, then overwritten). Writes go through a temporary file and an atomic rename, so
concurrent builds never see half an entry.
"""

from __future__ import annotations

import contextvars
import dataclasses
import hashlib
import json
import math
import os
import pickle
import sys
import tempfile
import threading
from collections.abc import Callable, Iterable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any, TypeVar

import cloudpickle

from ..errors import ArgumentTypeError, DesignError
from .slots import lent

__all__ = ["CACHE_FORMAT", "BuildResult", "DesignCache", "cached", "code_fingerprint", "design_key",
           "expected_seconds", "merge_run", "recording"]

#: format tag of every cache entry; entries with another tag are ignored
CACHE_FORMAT = "glidectl-cache-1"

T = TypeVar("T")


@lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """glidectl's version and a SHA-256 of its Python sources (a changed library invalidates every entry).

    Returns
    -------
    str
        ``"<version>:<first 16 hex digits of the hash>"``.

    Raises
    ------
    None
    """
    from .. import __version__

    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256(__version__.encode())
    for p in sorted(root.rglob("*.py")):
        h.update(str(p.relative_to(root)).encode())
        h.update(p.read_bytes())
    return f"{__version__}:{h.hexdigest()[:16]}"


def _sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def file_sha(path: str | Path) -> str | None:
    """SHA-256 of a file's content, or None when it cannot be read."""
    try:
        return _sha(Path(path).read_bytes())
    except OSError:
        return None


def settings_of(module: Any, quick: bool) -> str:
    """``repr`` of the settings a design uses: its ``QUICK`` or ``FULL`` preset ("" when it has none)."""
    s = getattr(module, "QUICK" if quick else "FULL", None)
    return "" if s is None else repr(s)


def expected_seconds(module: Any, quick: bool) -> float | None:
    """The build time a design file declares for itself, for scheduling and progress before its first build.

    A design may define ``EXPECTED_SECONDS = {"quick": s, "full": s}``: its measured build time (s) with each
    preset on a 2-core machine. ``glidectl report`` uses the last recorded build time when there is one
    (``timings.json``) and this declaration otherwise, so a first cold build already starts the longest designs
    first and its progress bars have an estimate.

    Parameters
    ----------
    module : module
        The loaded design file.
    quick : bool
        Quick settings or full.

    Returns
    -------
    float or None
        The declared time (s), or None when the design declares none.

    Raises
    ------
    DesignError
        If ``EXPECTED_SECONDS`` is not a mapping of ``"quick"``/``"full"`` to finite non-negative seconds.
    """
    decl = getattr(module, "EXPECTED_SECONDS", None)
    if decl is None:
        return None
    where = getattr(module, "__file__", None) or getattr(module, "__name__", "the design")
    ok = isinstance(decl, Mapping) and set(decl) <= {"quick", "full"} and all(
        isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v) and v >= 0
        for v in decl.values())
    if not ok:
        raise DesignError(f"{where}: EXPECTED_SECONDS must be a dict like {{'quick': 12.0, 'full': 300.0}} "
                          f"(seconds, finite, >= 0), got {decl!r}")
    v = decl.get("quick" if quick else "full")
    return None if v is None else float(v)


def design_key(name: str, source: bytes, quick: bool, settings: str) -> str:
    """The cache key of one build of a design.

    Parameters
    ----------
    name : str
        Design name (file stem).
    source : bytes
        Content of the design file.
    quick : bool
        Quick settings or full.
    settings : str
        ``repr`` of the frozen settings dataclass the build uses (see :func:`settings_of`).

    Returns
    -------
    str
        Hex SHA-256 of the cache format, glidectl's :func:`code_fingerprint`, and the arguments.

    Raises
    ------
    ArgumentTypeError
        If ``source`` is not bytes.
    """
    if not isinstance(source, bytes):
        raise ArgumentTypeError(f"design source must be bytes, got {type(source).__name__}")
    blob = json.dumps([CACHE_FORMAT, code_fingerprint(), name, _sha(source), bool(quick), settings])
    return _sha(blob.encode())


@dataclass(frozen=True)
class BuildResult:
    """What one build of a design produced: its output files and how it was obtained.

    Attributes
    ----------
    name : str
        Design name; the files go to ``<out>/<name>/``.
    files : dict of str to bytes
        Output file names (``report.pdf``, ``numbers.json``, one PNG per figure) and their content.
    seconds : float
        Wall time of the computation (s); for a cache hit, that of the build that was cached.
    deps : dict of str to str
        Data files the design read (absolute paths) and their SHA-256.
    provenance : tuple of str
        Provenance hashes of the report's vehicles.
    from_cache : bool
        True when the result came from the cache.
    sub_hits, sub_misses : int
        Lookups of :func:`cached` inside the design that hit / missed.
    """

    name: str
    files: dict[str, bytes]
    seconds: float
    deps: dict[str, str] = field(default_factory=dict)
    provenance: tuple[str, ...] = ()
    from_cache: bool = False
    sub_hits: int = 0
    sub_misses: int = 0

    def write(self, out: str | Path) -> Path:
        """Write the files into ``<out>/<name>/`` and return the ``report.pdf`` path."""
        target = Path(out) / self.name
        target.mkdir(parents=True, exist_ok=True)
        for fname, data in self.files.items():
            (target / fname).write_bytes(data)
        return target / "report.pdf"


def _atomic_pickle(path: Path, obj: Any) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-", suffix=".pkl")
    try:
        with os.fdopen(fd, "wb") as f:
            cloudpickle.dump(obj, f, protocol=pickle.HIGHEST_PROTOCOL)  # closures and lambdas in results too
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _load_pickle(path: Path) -> Any:
    """The pickled object, or None when the file is missing or unreadable (corrupt entries are removed)."""
    try:
        with open(path, "rb") as f:
            return pickle.load(f)
    except FileNotFoundError:
        return None
    except Exception:  # truncated, garbage, an old class layout: ignore and rebuild
        path.unlink(missing_ok=True)
        return None


class DesignCache:
    """The cache folder ``<out>/.cache`` of a report build.

    Parameters
    ----------
    root : str or Path
        The cache folder (created on the first write).

    Raises
    ------
    ArgumentTypeError
        If ``root`` is not a path.
    """

    def __init__(self, root: str | Path) -> None:
        if not isinstance(root, str | os.PathLike):
            raise ArgumentTypeError(f"cache root must be a path, got {type(root).__name__}")
        self.root = Path(root)

    def _entry(self, name: str, key: str) -> Path:
        return self.root / "designs" / name / f"{key}.pkl"

    def load(self, name: str, key: str) -> BuildResult | None:
        """The cached build of design ``name`` under ``key``, when every file it read is unchanged.

        Parameters
        ----------
        name : str
            Design name.
        key : str
            Its :func:`design_key`.

        Returns
        -------
        BuildResult or None
            The cached result (``from_cache=True``), or None on a miss, a changed input file or a corrupt entry.

        Raises
        ------
        None
        """
        entry = _load_pickle(self._entry(name, key))
        if not (isinstance(entry, dict) and entry.get("format") == CACHE_FORMAT and entry.get("key") == key
                and isinstance(entry.get("result"), BuildResult)):
            return None
        res: BuildResult = entry["result"]
        if any(file_sha(p) != h for p, h in res.deps.items()):
            return None
        return dataclasses.replace(res, from_cache=True)

    def store(self, key: str, result: BuildResult) -> None:
        """Store a build under ``key`` (older entries of the same design are removed).

        Parameters
        ----------
        key : str
            Its :func:`design_key`.
        result : BuildResult
            The build.

        Raises
        ------
        OSError
            If the cache folder cannot be written.
        """
        path = self._entry(result.name, key)
        for old in path.parent.glob("*.pkl") if path.parent.is_dir() else ():
            if old != path:
                old.unlink(missing_ok=True)
        _atomic_pickle(path, {"format": CACHE_FORMAT, "key": key,
                              "result": dataclasses.replace(result, from_cache=False, sub_hits=0, sub_misses=0)})

    # ---------------------------------------------------------------- timings of the last builds
    @property
    def timings_path(self) -> Path:
        return self.root / "timings.json"

    def timings(self) -> dict[str, float]:
        """Last build times (s) by ``"<name>:quick"`` / ``"<name>:full"`` ({} when none or unreadable)."""
        try:
            data = json.loads(self.timings_path.read_text())
        except (OSError, ValueError):
            return {}
        if not isinstance(data, dict):
            return {}
        return {k: float(v) for k, v in data.items() if isinstance(v, int | float)}

    def estimate(self, name: str, quick: bool) -> float | None:
        """Last build time of a design with these settings (s), or None when never built."""
        return self.timings().get(f"{name}:{'quick' if quick else 'full'}")

    def record_timings(self, seconds: Mapping[str, float], quick: bool) -> None:
        """Merge build times (s) by design name into ``timings.json``."""
        data = self.timings()
        data.update({f"{n}:{'quick' if quick else 'full'}": round(float(t), 3) for n, t in seconds.items()})
        self.root.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=self.root, prefix=".tmp-", suffix=".json")
        with os.fdopen(fd, "w") as f:
            json.dump(data, f, indent=1, sort_keys=True)
        os.replace(tmp, self.timings_path)


# ------------------------------------------------------------------ reads recorded while a design runs
@dataclass
class _Run:
    """State of one design run in this thread/process: the data files it reads, the sub-result cache."""

    cache_root: Path | None
    refresh: bool = False
    build: str | None = None    # id of the build this run belongs to (entries it wrote are reused under refresh)
    lock: bool = True           # cached() waits for another process computing the same key
    reads: set[str] = field(default_factory=set)
    hits: int = 0
    misses: int = 0


_ACTIVE: contextvars.ContextVar[_Run | None] = contextvars.ContextVar("glidectl_report_run", default=None)
_SKIP_SUFFIXES = (".py", ".pyc", ".pyd", ".so", ".dll", ".dylib", ".pth", ".ttf", ".otf", ".afm", ".pfb")
_hook_installed = False


def _skip_dirs() -> tuple[str, ...]:
    dirs = {sys.prefix, sys.base_prefix, sys.exec_prefix}
    try:
        import matplotlib

        dirs |= {matplotlib.get_cachedir(), matplotlib.get_configdir()}
    except Exception:  # pragma: no cover - matplotlib is a dependency
        pass
    dirs |= {"/proc", "/sys", "/dev", "/etc"}  # system state, never a design's input
    return tuple(os.path.join(os.path.realpath(d), "") for d in dirs if d)


def _audit(event: str, args: tuple[Any, ...]) -> None:
    """Audit hook: record files opened for reading while a design runs (never raises)."""
    if event != "open":
        return
    run = _ACTIVE.get()
    if run is None:
        return
    try:
        path, mode, flags = args
        if not isinstance(path, str | bytes | os.PathLike):
            return
        if mode is not None:
            if any(c in mode for c in "wax+"):
                return
        elif flags & (os.O_WRONLY | os.O_RDWR):
            return
        p = os.fsdecode(path)
        if p.endswith(_SKIP_SUFFIXES):
            return
        run.reads.add(os.path.abspath(p))
    except Exception:  # an audit hook must never disturb the program
        return


def _install_hook() -> None:
    global _hook_installed
    if not _hook_installed:
        sys.addaudithook(_audit)
        _hook_installed = True


def merge_run(reads: Iterable[str], hits: int, misses: int) -> None:
    """Add what a part of the design run in another process read and hit to this process's active recording.

    Parameters
    ----------
    reads : iterable of str
        Absolute paths of the files the part opened for reading.
    hits, misses : int
        The part's :func:`cached` hits and misses.

    Raises
    ------
    None
        Outside a recording nothing happens.
    """
    run = _ACTIVE.get()
    if run is not None:
        run.reads.update(reads)
        run.hits += int(hits)
        run.misses += int(misses)


def _is_data_file(p: str, skip: tuple[str, ...], package: str) -> bool:
    real = os.path.realpath(p)
    if real.startswith(package):  # glidectl's own data (vehicle presets), even when installed in site-packages
        return os.path.isfile(real)
    return not real.startswith(skip) and os.path.isfile(real)


class recording:
    """Context manager for one design run: records the data files read and activates :func:`cached`.

    Parameters
    ----------
    cache_root : Path or None
        The cache folder for :func:`cached` (None: :func:`cached` computes without caching).
    refresh : bool
        :func:`cached` computes every value again and overwrites the cache (``--no-cache``), except values written
        by the same ``build``.
    build : str, optional
        Id of the build the run belongs to (random, one per ``glidectl report`` call): under ``refresh``, a value
        another design of the same build has cached is reused, so one cold build computes a shared value once.
    lock : bool
        :func:`cached` waits while another process computes the same key (False inside a part of a design that
        holds such a lock, see :func:`holds_lock`).

    Raises
    ------
    None
    """

    def __init__(self, cache_root: Path | None, refresh: bool = False, build: str | None = None,
                 lock: bool = True) -> None:
        self.run = _Run(None if cache_root is None else Path(cache_root), bool(refresh), build, bool(lock))
        self._token: contextvars.Token[_Run | None] | None = None

    def __enter__(self) -> recording:
        _install_hook()
        self._token = _ACTIVE.set(self.run)
        return self

    def __exit__(self, *exc: Any) -> None:
        assert self._token is not None
        _ACTIVE.reset(self._token)

    def deps(self, exclude: Iterable[str | Path] = ()) -> dict[str, str]:
        """The data files read during the run and their SHA-256 (files under ``exclude`` folders left out)."""
        skip = _skip_dirs() + tuple(os.path.join(os.path.realpath(d), "") for d in exclude)
        package = os.path.join(os.path.realpath(Path(__file__).resolve().parents[1]), "")
        out = {}
        for p in sorted(self.run.reads):
            if _is_data_file(p, skip, package):
                h = file_sha(p)
                if h is not None:
                    out[os.path.realpath(p)] = h
        return out


def _digest(obj: Any) -> Any:
    """A JSON-able canonical form of a cache key part."""
    import numpy as np

    if obj is None or isinstance(obj, bool | int | str):
        return obj
    if isinstance(obj, float):
        return repr(obj)
    if isinstance(obj, bytes):
        return ["bytes", _sha(obj)]
    if isinstance(obj, np.ndarray):
        a = np.ascontiguousarray(obj)
        return ["ndarray", str(a.dtype), list(a.shape), _sha(a.tobytes())]
    if isinstance(obj, np.generic):
        return _digest(obj.item())
    if isinstance(obj, list | tuple):
        return [type(obj).__name__, [_digest(x) for x in obj]]
    if isinstance(obj, Mapping):
        return ["dict", sorted([str(k), _digest(v)] for k, v in obj.items())]
    prov = getattr(obj, "provenance", None)
    if isinstance(prov, str):  # a Vehicle (or any result carrying the vehicle's provenance)
        return [type(obj).__name__, prov, repr(obj)]
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return [type(obj).__qualname__, repr(obj)]
    raise ArgumentTypeError(f"cache key part of type {type(obj).__name__} has no canonical form; use numbers, "
                            "strings, tuples, arrays, dicts, dataclasses (settings) or vehicles")


def cached(key: Any, fn: Callable[[], T]) -> T:
    """Return ``fn()``, cached across builds when a ``glidectl report`` build with a cache is running.

    Inside ``glidectl report`` the value is pickled into ``<out>/.cache/results/`` under a hash of ``key`` and
    glidectl's version and source code; a later build with the same key loads it instead of calling ``fn``
    (``--no-cache`` calls ``fn`` and overwrites the entry, except an entry written by another design of the same
    build: two designs that cache the same computation under the same key compute it once per build). While one
    process computes a key, another that asks for it waits and then loads it (a lock file next to the entry).
    Outside a build (a plain ``design()`` call) ``fn()`` is simply called.
    An unreadable entry is ignored and recomputed.

    Parameters
    ----------
    key : Any
        What the value depends on: numbers, strings, tuples, lists, dicts, NumPy arrays, the design's frozen
        settings dataclass (its repr), vehicles (their provenance). Name the computation too, e.g.
        ``("ctol_certificate", s.ctol_degree, s.ctol_k3, veh)``.
    fn : callable
        Computes the value (no arguments); the value must be picklable.

    Returns
    -------
    Any
        ``fn()`` or the cached value.

    Raises
    ------
    ArgumentTypeError
        If ``fn`` is not callable or a key part has no canonical form.

    Examples
    --------
    >>> cert = cached(("vdp", s.vdp_degree), lambda: gc.certify_roa(vdp, degree=s.vdp_degree))  # doctest: +SKIP
    """
    if not callable(fn):
        raise ArgumentTypeError(f"cached(key, fn): fn must be callable, got {type(fn).__name__}")
    k = _sha(json.dumps([CACHE_FORMAT, code_fingerprint(), _digest(key)]).encode())
    run = _ACTIVE.get()
    if run is None or run.cache_root is None:
        return fn()
    path = run.cache_root / "results" / f"{k}.pkl"
    with _key_lock(path, run.lock):
        entry = _load_pickle(path)
        if (isinstance(entry, dict) and entry.get("format") == CACHE_FORMAT and entry.get("key") == k
                and "value" in entry and (not run.refresh or (run.build is not None
                                                              and entry.get("build") == run.build))):
            run.hits += 1
            return entry["value"]
        run.misses += 1
        value = fn()
        try:
            _atomic_pickle(path, {"format": CACHE_FORMAT, "key": k, "build": run.build, "value": value})
        except (OSError, pickle.PicklingError, TypeError, AttributeError):
            pass  # an unpicklable value is simply not cached
        return value


_HELD = threading.local()   # .active: this thread computes a cached value under its key's lock (see _key_lock)


def holds_lock() -> bool:
    """Whether this thread is computing a :func:`cached` value under its key's lock (then the parts it starts do
    not lock: see :func:`_key_lock`).

    Returns
    -------
    bool

    Raises
    ------
    None
    """
    return bool(getattr(_HELD, "active", False))


def _wait_for(fcntl: Any, f: Any) -> bool:
    """Take the exclusive lock of the open file ``f`` (``fcntl``: the module, imported by the caller), waiting for
    its holder; True if taken. On a dask worker the thread secedes from the worker's pool while it waits
    (``distributed.secede``), so a waiter never takes the slot that the holder's own parts would need."""
    try:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        return True
    except BlockingIOError:
        pass
    except OSError:
        return False
    seceded = False
    try:
        from distributed import get_worker, secede

        get_worker()                                    # ValueError: not on a dask worker
        secede()
        seceded = True
    except (ImportError, ValueError):
        pass
    try:
        with lent():                # no compute slot is held while waiting (glidectl.report.slots)
            fcntl.flock(f.fileno(), fcntl.LOCK_EX)
        return True
    except OSError:
        return False
    finally:
        if seceded:
            from distributed import rejoin

            rejoin()


@contextmanager
def _key_lock(path: Path, enabled: bool = True) -> Iterator[None]:
    """Hold an exclusive lock on ``<path>.lock`` (``fcntl.flock``): a design that needs a value another design
    is computing in the same build waits for it and then reads it, instead of computing it again.

    Only the outermost :func:`cached` call of a thread locks, and parts started under a lock do not lock either
    (``enabled`` False), so a thread that holds a lock never waits for another: the waits cannot form a cycle. The
    lock goes with the process (a killed holder releases it). Where locks are not available (no ``fcntl``, a file
    system that refuses them) the value is computed without one, as before: at worst twice."""
    if not enabled or holds_lock():
        yield
        return
    try:
        import fcntl  # POSIX only: elsewhere no lock

        path.parent.mkdir(parents=True, exist_ok=True)
        f = open(path.with_suffix(".lock"), "a+b")      # closed below, after the unlock
    except (ImportError, OSError):
        yield
        return
    try:
        locked = _wait_for(fcntl, f)
        _HELD.active = True         # nested calls of this thread (and the parts it starts) do not lock
        try:
            yield
        finally:
            _HELD.active = False
            if locked:
                fcntl.flock(f.fileno(), fcntl.LOCK_UN)
    finally:
        f.close()
