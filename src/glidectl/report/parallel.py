"""Building many designs: the cache lookups, a process pool or a ``dask.distributed`` cluster, progress display.

:func:`build_designs` is what ``glidectl report all [--jobs N] [--scheduler ADDRESS] [--no-cache]`` runs. Each
design that is not in the cache is built by :func:`build_one`, a top-level function of picklable arguments (the
design's name, path and source text), so it runs unchanged in this process, in a spawned worker process or on a
dask worker; it returns the files the design wrote as bytes (a :class:`~glidectl.report.cache.BuildResult`), and
this process writes them into ``<out>/<name>/`` and the cache. A serial build, a pool build and a cluster build
therefore write the same files.

Progress: a pool worker sends its design's messages through a queue, a dask worker through the scheduler's event
topic :data:`_DASK_TOPIC` (``Worker.log_event``, ``Client.subscribe_topic``); the first message, :data:`_STARTED`,
is sent when the worker starts the design, and the design's start line is printed then (not when it is queued).
"""

from __future__ import annotations

import multiprocessing
import os
import sys
import tempfile
import threading
import time
import traceback
import uuid
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TextIO

from ..errors import ArgumentError, DesignError, GlidectlError
from .cache import BuildResult, DesignCache, design_key, expected_seconds, recording, settings_of
from .designs import Design, load_design_source
from .parts import parts_context
from .slots import Slots, holding, install
from .threads import worker_threads

__all__ = ["DesignFailure", "build_designs", "build_one", "dask_client", "require_dask"]


@dataclass(frozen=True)
class DesignFailure:
    """A design that raised: its name and the one-line message (with the design file's line for its own errors)."""

    name: str
    message: str


def _where(exc: BaseException) -> str:
    frames = traceback.extract_tb(exc.__traceback__)
    return f" ({Path(frames[-1].filename).name}:{frames[-1].lineno})" if frames else ""


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    if isinstance(exc, GlidectlError):
        return text
    return f"{type(exc).__name__}: {text}{_where(exc)}"


# a queue for progress messages, given to pool workers when they start (queues are inherited, not pickled)
_WORKER_QUEUE: Any = None


#: first message of a design in a pool worker: the worker has taken it (its start line is printed then, not when the
#: pool hands it to its call queue, which happens before a worker is free)
_STARTED = "\x00started"

#: the end of a design on a dask cluster (its result is here), put in order among the workers' messages
_ENDED = "\x00ended"


def _init_worker(queue: Any, slots: Slots | None = None) -> None:
    global _WORKER_QUEUE
    _WORKER_QUEUE = queue
    install(slots)      # the build's compute slots (glidectl.report.slots), shared with the design's parts pools


def build_one(name: str, path: str, source: bytes, quick: bool, cache_root: str | None = None,
              progress: Callable[[str], None] | None = None, refresh: bool = False, jobs: int = 1,
              dask: bool = False, start_method: str = "spawn", build: str | None = None) -> BuildResult | DesignFailure:
    """Run one design and return the files its report consists of (nothing is written outside a temporary folder).

    Parameters
    ----------
    name : str
        Design name (file stem).
    path : str
        The design file (used when it exists with content ``source``).
    source : bytes
        Content of the design file (loaded from a temporary copy where ``path`` differs, e.g. on a remote worker).
    quick : bool
        Use the design's quick settings.
    cache_root : str, optional
        Cache folder for the sub-results a design caches with :func:`glidectl.report.cached` (None: no caching).
    progress : callable, optional
        ``progress(message)``; in a pool worker, messages go to the parent's display.
    refresh : bool
        Sub-results are computed again (and the cache overwritten) instead of looked up.
    jobs : int
        Worker processes the design's :func:`~glidectl.report.map_parts` calls may use (1: serial).
    dask : bool
        The design runs on a dask worker: its parts are submitted to the same cluster.
    start_method : str
        Start method of the parts' process pool (``"spawn"`` by default).
    build : str, optional
        Id of the build (one per :func:`build_designs` call): under ``refresh``, values that another design of the
        same build cached are reused (:func:`~glidectl.report.cached`).

    Returns
    -------
    BuildResult or DesignFailure
        The files (``report.pdf``, PNGs, ``numbers.json``), the data files the design read and the timing; or the
        one-line error when the design failed.

    Raises
    ------
    None
        Errors of the design are returned as :class:`DesignFailure`.
    """
    queue = _WORKER_QUEUE
    if progress is None:
        progress = (lambda m: queue.put((name, m))) if queue is not None else (lambda m: None)
        if queue is not None:
            queue.put((name, (_STARTED, os.getpid())))   # the worker: its previous design's result is already sent
    try:
        design = load_design_source(name, path, source)
        with holding(), tempfile.TemporaryDirectory(prefix="glidectl-build-") as tmp:
            with recording(None if cache_root is None else Path(cache_root), refresh, build) as rec, \
                    parts_context(name, path, source, jobs, cache_root, refresh, dask, start_method, build):
                t0 = time.perf_counter()
                rep = design.report(progress, quick)
                progress("writing the report")
                rep.write(Path(tmp) / name)
                seconds = time.perf_counter() - t0
            files = {p.name: p.read_bytes() for p in sorted((Path(tmp) / name).iterdir()) if p.is_file()}
            deps = rec.deps(exclude=[tmp] + ([cache_root] if cache_root else []))
        return BuildResult(name, files, seconds, deps, tuple(v.provenance for v in rep.vehicles), False,
                           rec.run.hits, rec.run.misses)
    except Exception as exc:
        return DesignFailure(name, _one_line(exc))


#: the scheduler event topic through which dask workers send progress; each message is ``[build, name, text]``,
#: ``build`` the id of the build that submitted the design (other builds on the same scheduler are ignored)
_DASK_TOPIC = "glidectl-report-progress"


def _build_on_dask(build: str, name: str, path: str, source: bytes, quick: bool, cache_root: str | None,
                   refresh: bool) -> BuildResult | DesignFailure:
    """:func:`build_one` on a dask worker, its progress sent to the client through :data:`_DASK_TOPIC`: first
    :data:`_STARTED` (the worker has started the design), then the design's messages."""
    from distributed import get_worker

    worker = get_worker()

    def progress(msg: str) -> None:
        worker.log_event(_DASK_TOPIC, [build, name, str(msg)])  # msgpack: a list of strings

    progress(_STARTED)
    return build_one(name, path, source, quick, cache_root, progress=progress, refresh=refresh, jobs=2, dask=True,
                     build=build)


def require_dask() -> None:
    """Check that ``dask.distributed`` can be imported.

    Raises
    ------
    DesignError
        If it cannot: install the ``dask`` extra.
    """
    try:
        import distributed  # noqa: F401
    except ImportError as exc:
        raise DesignError("--scheduler needs dask.distributed, which is not installed: pip install "
                          "'glidectl[dask]' (in a clone: pip install -e \".[dask]\")") from exc


def dask_client(address: Any) -> Any:
    """A ``dask.distributed`` client for a scheduler address (or the client itself when one is given).

    Parameters
    ----------
    address : str or distributed.Client
        Scheduler address, e.g. ``"tcp://10.0.0.5:8786"``.

    Returns
    -------
    distributed.Client

    Raises
    ------
    DesignError
        If dask.distributed is not installed (install the ``dask`` extra) or the scheduler cannot be reached.
    """
    require_dask()
    from distributed import Client

    if isinstance(address, Client):
        return address
    try:
        return Client(address, timeout="20s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise DesignError(f"cannot reach the dask scheduler at {address!r}: {exc}") from exc


# ------------------------------------------------------------------------------------------ display
def _fmt_s(t: float | None) -> str:
    if t is None:
        return "?"
    return f"{t:.1f} s" if t < 120 else f"{t / 60:.1f} min"


class _Display:
    """Progress of a build: a bar per running design on a terminal (tqdm), plain lines otherwise."""

    def __init__(self, designs: Sequence[Design], quick: bool, estimates: dict[str, float | None],
                 stream: TextIO | None = None, bars: bool | None = None, declared: frozenset[str] = frozenset()
                 ) -> None:
        self.stream = stream or sys.stdout
        self.quick = quick
        self.index = {d.name: i for i, d in enumerate(designs, 1)}
        self.titles = {d.name: d.title for d in designs}
        self.n = len(designs)
        self.estimates = estimates
        self.declared = declared      # estimates from the designs' EXPECTED_SECONDS (no build recorded yet)
        self.t0: dict[str, float] = {}
        self.steps: dict[str, int] = {}
        if bars is None:
            bars = bool(getattr(self.stream, "isatty", lambda: False)())
        self.tqdm: Any = None
        if bars:
            try:
                from tqdm import tqdm

                self.tqdm = tqdm
            except ImportError:  # pragma: no cover - tqdm is a dependency
                self.tqdm = None
        self.bars: dict[str, Any] = {}
        self.lock = threading.Lock()
        self._stop = threading.Event()
        self._ticker: threading.Thread | None = None

    def _tag(self, name: str) -> str:
        return f"[{self.index[name]}/{self.n}] {name}"

    def line(self, text: str) -> None:
        if self.tqdm is not None:
            self.tqdm.write(text, file=self.stream)
        else:
            print(text, file=self.stream, flush=True)

    def start(self, name: str) -> None:
        with self.lock:
            if name in self.t0:         # once per design
                return
            self.t0[name] = time.perf_counter()
            est = self.estimates.get(name)
            q = " (quick settings)" if self.quick else ""
            if self.tqdm is not None:
                self.bars[name] = self.tqdm(total=round(est, 1) if est else None, desc=name, unit="s",
                                            position=len(self.bars), leave=False, file=self.stream,
                                            bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.0f}/{total:.0f} s "
                                                       "{postfix}" if est else "{desc}: {n:.0f} s {postfix}")
                self._start_ticker()
            else:
                what = "expected" if name in self.declared else "last build"
                self.line(f"{self._tag(name)}: {self.titles[name]}{q} ({what}: {_fmt_s(est)})")

    def message(self, name: str, msg: str) -> None:
        with self.lock:
            if name not in self.t0:
                return
            self.steps[name] = self.steps.get(name, 0) + 1
            elapsed = time.perf_counter() - self.t0[name]
            bar = self.bars.get(name)
            if bar is not None:
                bar.set_postfix_str(msg[:60], refresh=False)
                self._tick(name, bar)
            else:
                self.line(f"  {name} [{self.steps[name]:2d}] {elapsed:7.1f} s  {msg}")

    def _tick(self, name: str, bar: Any) -> None:
        elapsed = time.perf_counter() - self.t0[name]
        total = bar.total
        bar.n = min(elapsed, total * 0.99) if total else elapsed
        bar.refresh()

    def _start_ticker(self) -> None:
        if self._ticker is not None:
            return

        def loop() -> None:
            while not self._stop.wait(0.5):
                with self.lock:
                    for name, bar in list(self.bars.items()):
                        self._tick(name, bar)

        self._ticker = threading.Thread(target=loop, daemon=True)
        self._ticker.start()

    def done(self, res: BuildResult, pdf: Path) -> None:
        with self.lock:
            bar = self.bars.pop(name := res.name, None)
            if bar is not None:
                bar.close()
            if res.from_cache:
                how = f"cache hit, built in {_fmt_s(res.seconds)}"
                took = 0.0
            else:
                # the design's own build time, measured in its worker (a pool hands the next design to a worker
                # before one is free, so the time since the start line can include a wait in the queue)
                took = res.seconds
                sub = res.sub_hits + res.sub_misses
                how = "computed" + (f", sub-results {res.sub_hits}/{sub} from cache" if sub else "")
            self.line(f"{self._tag(name)}: done in {took:.1f} s ({how}) -> {pdf}")

    def failed(self, fail: DesignFailure) -> None:
        with self.lock:
            bar = self.bars.pop(fail.name, None)
            if bar is not None:
                bar.close()
            self.line(f"{self._tag(fail.name)}: failed: {fail.message}")

    def close(self) -> None:
        self._stop.set()
        for bar in self.bars.values():
            bar.close()


# ------------------------------------------------------------------------------------------ the build
def build_designs(designs: Sequence[Design], out: str | Path, *, quick: bool = False, jobs: int | None = None,
                  scheduler: Any = None, use_cache: bool = True, stream: TextIO | None = None,
                  bars: bool | None = None, mp_context: Any = None) -> list[BuildResult]:
    """Build designs into ``<out>/<name>/``: cached ones from ``<out>/.cache``, the others serially, on a process
    pool or on a dask cluster.

    Parameters
    ----------
    designs : sequence of Design
        Loaded designs (:func:`~glidectl.report.load_design`).
    out : str or Path
        Parent output folder (its ``.cache`` subfolder holds the cache and the last build times).
    quick : bool
        Use the designs' quick settings.
    jobs : int, optional
        Processes that compute at once (default ``os.cpu_count()``): the designs run on a pool of ``2 * jobs``
        workers that share ``jobs`` compute slots with their parts (:mod:`glidectl.report.slots`); 1 builds in
        this process.
    scheduler : str or distributed.Client, optional
        Address of a ``dask.distributed`` scheduler: the designs are built on its workers instead.
    use_cache : bool
        Look results up in the cache; False forces a cold build (whose results still refresh the cache).
    stream : text stream, optional
        Where progress goes (default ``sys.stdout``).
    bars : bool, optional
        Progress bars (default: when ``stream`` is a terminal); plain lines otherwise.
    mp_context : multiprocessing context, optional
        Start method of the pool and of the designs' part pools (default ``spawn``, safe with threads and on every
        platform).

    Returns
    -------
    list of BuildResult
        One per design, in the order given.

    Raises
    ------
    ArgumentError
        If ``jobs`` is not a positive integer.
    DesignError
        If a design failed (the first failure's one-line message; the other designs are still built), declares an
        invalid ``EXPECTED_SECONDS`` (:func:`~glidectl.report.cache.expected_seconds`), or the dask scheduler cannot
        be used.
    """
    if jobs is None:
        jobs = os.cpu_count() or 1
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise ArgumentError(f"jobs must be a positive integer (worker processes), got {jobs!r}")
    out = Path(out)
    store = DesignCache(out / ".cache")
    timings = store.timings()
    tag = "quick" if quick else "full"
    # the last build's time, else the design's own declaration (a first cold build is ordered longest first too)
    estimates = {d.name: timings.get(f"{d.name}:{tag}", expected_seconds(d.module, quick)) for d in designs}
    declared = frozenset(d.name for d in designs if f"{d.name}:{tag}" not in timings and estimates[d.name] is not None)
    display = _Display(designs, quick, estimates, stream, bars, declared)
    results: dict[str, BuildResult] = {}
    failures: list[DesignFailure] = []
    todo: list[tuple[Design, str, bytes]] = []
    try:
        for d in designs:
            source = d.path.read_bytes()
            key = design_key(d.name, source, quick, settings_of(d.module, quick))
            hit = store.load(d.name, key) if use_cache else None
            if hit is not None:
                display.t0[d.name] = time.perf_counter()
                display.done(hit, hit.write(out))
                results[d.name] = hit
            else:
                todo.append((d, key, source))
        todo.sort(key=lambda t: -(estimates.get(t[0].name) or 0.0))  # longest first: shortest makespan
        cache_root = str(store.root)
        refresh = not use_cache
        build = uuid.uuid4().hex     # this build's id: what one design caches, another reuses (cold builds too)
        keys = {d.name: key for d, key, _ in todo}

        def finish(res: BuildResult | DesignFailure) -> None:
            if isinstance(res, DesignFailure):
                display.failed(res)
                failures.append(res)
                return
            pdf = res.write(out)
            display.done(res, pdf)
            results[res.name] = res
            store.record_timings({res.name: res.seconds}, quick)
            try:
                store.store(keys[res.name], res)
            except OSError as exc:
                display.line(f"  {res.name}: not cached ({exc})")

        method = mp_context.get_start_method() if mp_context is not None else "spawn"
        if scheduler is not None:
            _run_dask(todo, scheduler, quick, cache_root, refresh, display, finish, build)
        elif jobs == 1 or len(todo) <= 1:
            for d, _, source in todo:
                display.start(d.name)
                finish(build_one(d.name, str(d.path), source, quick, cache_root,
                                 progress=lambda m, n=d.name: display.message(n, m), refresh=refresh, jobs=jobs,
                                 start_method=method, build=build))
        else:
            # twice as many design processes as slots: a design that waits for its parts (or another's value) has
            # lent its slot, and another design takes it instead of waiting for a free process (glidectl.report.slots)
            _run_pool(todo, min(2 * jobs, len(todo)), quick, cache_root, refresh, display, finish, mp_context, jobs,
                      build)
    finally:
        display.close()
    if failures:
        raise DesignError(failures[0].message)
    return [results[d.name] for d in designs]


def _result(future: Any, name: str) -> BuildResult | DesignFailure:
    """A finished job's result; a worker that died (or a cluster error) becomes the design's failure."""
    try:
        return future.result()
    except Exception as exc:
        return DesignFailure(name, f"building {name} failed in its worker: {type(exc).__name__}: "
                                   f"{' '.join(str(exc).split())}")


def _drain(queue: Any, display: _Display, started: Callable[[str, int], None] | None = None) -> None:
    """Show the pool workers' messages; a design's start message ``(_STARTED, pid)`` goes to ``started(name, pid)``
    (or starts its line)."""
    import queue as queue_mod

    while True:
        try:
            name, msg = queue.get_nowait()
        except (queue_mod.Empty, EOFError, OSError):
            return
        if isinstance(msg, tuple) and msg and msg[0] == _STARTED:
            if started is not None:
                started(name, msg[1])
            else:
                display.start(name)
        else:
            display.message(name, msg)


def _run_pool(todo: list[tuple[Design, str, bytes]], workers: int, quick: bool, cache_root: str, refresh: bool,
              display: _Display, finish: Callable[[Any], None], mp_context: Any, jobs: int,
              build: str | None = None) -> None:
    """The designs on a process pool, their lines in the order of events on the workers: a worker sends a design's
    result before it takes the next design, so when a design starts on a worker (its first message names the
    worker's pid), the design that worker ran before is finished first (its future is done, or about to be)."""
    ctx = mp_context or multiprocessing.get_context("spawn")
    queue = ctx.Queue()
    slots = Slots(jobs, ctx)        # at most `jobs` of the designs and their parts compute at once
    # cores // jobs threads per worker, not cores // workers: each design may start a parts pool of `jobs` workers,
    # which inherit this share (a larger one would oversubscribe the cores when the parts run)
    with worker_threads(jobs), ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_worker,
                                                   initargs=(queue, slots)) as ex:
        pending: dict[Any, str] = {}
        for d, _, source in todo:
            pending[ex.submit(build_one, d.name, str(d.path), source, quick, cache_root, refresh=refresh,
                              jobs=jobs, start_method=ctx.get_start_method(), build=build)] = d.name
        future_of = {name: f for f, name in pending.items()}
        on_worker: dict[int, str] = {}          # worker pid -> the design it runs

        def close(f: Any) -> None:
            name = pending.pop(f)
            display.start(name)     # no-op unless the worker died before its first message
            finish(_result(f, name))

        def started(name: str, pid: int) -> None:
            before = on_worker.get(pid)
            if before is not None and future_of[before] in pending:
                future_of[before].exception()   # waits for the result the worker has already sent
                close(future_of[before])
            on_worker[pid] = name
            display.start(name)

        while pending:
            _drain(queue, display, started)     # a worker's first message starts its design's line
            for f in [f for f in pending if f.done()]:
                _drain(queue, display, started)
                if f in pending:
                    close(f)
            time.sleep(0.1)
    queue.close()


def _run_dask(todo: list[tuple[Design, str, bytes]], scheduler: Any, quick: bool, cache_root: str, refresh: bool,
              display: _Display, finish: Callable[[Any], None], build: str | None = None) -> None:
    """The designs on a dask cluster; the display gets its events in the order they happened on the workers.

    The designs' messages come through :data:`_DASK_TOPIC` to :func:`receive` (the client's event loop thread), in
    the order the workers sent them, and a design's messages come before its result (one stream from worker to
    scheduler and one from scheduler to client). ``receive`` puts them in ``events``; before a design's first
    message (its worker has started it) it puts the end of every design whose result is already here, so a design
    that waited for a thread starts its line after the design it waited for has its summary line.
    """
    import queue as queue_mod

    client = dask_client(scheduler)
    own = client is not scheduler
    build = build or uuid.uuid4().hex
    events: queue_mod.Queue[tuple[str, str]] = queue_mod.Queue()
    lock = threading.Lock()
    pending: dict[str, Any] = {}     # design name -> future, until its end is in ``events``

    def ended() -> None:             # with ``lock`` held
        for name in [n for n, f in pending.items() if f.done()]:
            events.put((name, _ENDED))
            del pending[name]

    def receive(event: tuple[float, Any]) -> None:
        bid, name, msg = event[1]
        if bid != build:             # another build using the same scheduler
            return
        with lock:
            if msg == _STARTED:
                ended()
            events.put((name, msg))

    # subscribed before the first submission (same stream to the scheduler), so no message is missed
    client.subscribe_topic(_DASK_TOPIC, receive)
    try:
        futures = {}
        with lock:
            for d, _, source in todo:
                futures[d.name] = pending[d.name] = client.submit(
                    _build_on_dask, build, d.name, str(d.path), source, quick, cache_root, refresh, pure=False)
        left = len(futures)
        while left:
            with lock:
                ended()
            while True:
                try:
                    name, msg = events.get_nowait()
                except queue_mod.Empty:
                    break
                if msg == _STARTED:
                    display.start(name)
                elif msg == _ENDED:
                    display.start(name)     # no-op unless the design failed before its first message
                    finish(_result(futures[name], name))
                    left -= 1
                else:
                    display.message(name, msg)
            time.sleep(0.1)
    finally:
        with lock:                   # the client keeps ``receive`` after unsubscribing: let it hold no futures
            pending.clear()
        try:
            client.unsubscribe_topic(_DASK_TOPIC)
        except Exception:  # a closed client or scheduler: nothing left to unsubscribe
            pass
        if own:
            client.close()
